"""What machine a measurement ran on, for the generated pages (BENCHMARKS.md,
docs/comparison/): one place for the CPU's name."""
import platform


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"
