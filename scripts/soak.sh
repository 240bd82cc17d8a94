#!/usr/bin/env bash
# Soak: does memory stay flat and is every observation kept over a long run (issue 18 item 5)?
#  (a) `startracker live` on the simulated sensors of rawlogs/live_sim.ini in real time for
#      --live-seconds (default 3600);
#  (b) replay of the 36,000-frame one-hour rawlog (README "One hour of tracking at 10 Hz"),
#      simulated first into OUT when missing (~0.5 GB of PNGs, an hour of one core), or of
#      --replay-rawlog FILE (e.g. (a)'s recording: live_soak.rawlog, 36,000 frames, with its
#      live_soak_tracker.ini; --replay-config INI, default <stem>_tracker.ini beside it).
# Each run's resident memory (VmRSS of /proc/PID/status) is sampled every second into
# OUT/<run>_rss.tsv and drawn to OUT/<run>_rss.png (gnuplot); OUT/soak_summary.txt holds RSS
# after warm-up vs at the end and the observation counts (live: delivered by the sensors vs
# recorded; replay: frames read vs frames in the summary).
#
# usage: scripts/soak.sh [--live-seconds N] [--skip-live] [--skip-replay] [--out DIR]
#                        [--build DIR] [--replay-rawlog FILE [--replay-config INI]]
# Long: run it with nice -n 10 in the background. Not part of ctest.
set -euo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
live_s=3600
out="$repo/out/soak"
build="$repo/build"
do_live=1
do_replay=1
replay_rawlog=""
replay_config=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --live-seconds) live_s=$2; shift 2 ;;
    --skip-live) do_live=0; shift ;;
    --skip-replay) do_replay=0; shift ;;
    --out) out=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --replay-rawlog) replay_rawlog=$2; shift 2 ;;
    --replay-config) replay_config=$2; shift 2 ;;
    -h|--help) sed -n 2,17p "$0"; exit 0 ;;
    *) echo "soak.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if ! [[ "$live_s" =~ ^[0-9]+$ ]] || [[ "$live_s" -lt 60 ]]; then
  echo "soak.sh: --live-seconds '$live_s': a whole number of seconds >= 60" >&2
  exit 2
fi
st="$build/app/startracker"
if [[ ! -x "$st" ]]; then
  echo "soak.sh: $st not built (cmake --build $build --target startracker)" >&2
  exit 2
fi
command -v gnuplot >/dev/null || { echo "soak.sh: gnuplot missing (scripts/install-deps.sh)" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
# A copy: a rebuild during an hour-long run must not replace the program under it. The
# launcher execs startracker-cli from its own folder: copy both.
cp "$st" "$out/startracker"
cp "$(dirname "$st")/startracker-cli" "$out/startracker-cli"
st="$out/startracker"
summary="$out/soak_summary.txt"
: >"$summary"

# Runs "$@" in the background, samples its VmRSS every second into $1.tsv; returns its exit
# code. The first argument is the run's name.
run_sampled() {
  local name=$1; shift
  local tsv="$out/${name}_rss.tsv" log="$out/${name}.log"
  echo "# elapsed_s rss_kB" >"$tsv"
  "$@" >"$log" 2>&1 &
  local pid=$! t0 now rss
  t0=$(date +%s.%N)
  while kill -0 "$pid" 2>/dev/null; do
    rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
    now=$(date +%s.%N)
    [[ -n "$rss" ]] && awk -v a="$now" -v b="$t0" -v r="$rss" 'BEGIN { printf "%.1f %s\n", a - b, r }' >>"$tsv"
    sleep 1
  done
  wait "$pid"
}

# RSS after warm-up (the first sample at or after 10 % of the run, at least 60 s) vs at the
# end, and the growth rate between them.
rss_summary() {
  local name=$1 tsv="$out/$1_rss.tsv"
  awk -v name="$name" '
    !/^#/ { t[n] = $1; r[n] = $2; n++; if ($2 > peak) peak = $2 }
    END {
      if (n < 2) { printf "%s: too few RSS samples\n", name; exit }
      warm = t[n - 1] * 0.1; if (warm < 60) warm = 60
      for (i = 0; i < n && t[i] < warm; i++) {}
      if (i >= n) i = 0
      # the mean of the last 10 samples: one sample can catch a frame being decoded
      m = (n - 10 > i) ? n - 10 : i; s = 0; k = 0
      for (j = m; j < n; j++) { s += r[j]; k++ }
      end_rss = s / k
      dt = (t[n - 1] - t[i]) / 60
      printf "%s: RSS %.1f MB after warm-up (t=%.0f s), %.1f MB at the end (t=%.0f s, mean of last %d samples), peak %.1f MB; growth %.3f MB/min\n",
        name, r[i] / 1024, t[i], end_rss / 1024, t[n - 1], k, peak / 1024,
        (dt > 0 ? (end_rss - r[i]) / 1024 / dt : 0)
    }' "$tsv" | tee -a "$summary"
}

plot_rss() {
  local name=$1 title=$2
  gnuplot <<EOF
set terminal pngcairo size 900,450
set output "$out/${name}_rss.png"
set title "$title"
set xlabel "elapsed [min]"
set ylabel "resident memory (VmRSS) [MB]"
set yrange [0:*]
set grid
plot "$out/${name}_rss.tsv" using (\$1/60):(\$2/1024) with lines lw 2 title "VmRSS"
EOF
}

if [[ $do_live == 1 ]]; then
  echo "soak: live for $live_s s -> $out/live.log" | tee -a "$summary"
  rm -rf "$out/live_soak.rawlog" "$out/live_soak_Images" "$out/live_soak_tracker.ini"
  rc=0
  run_sampled live "$st" live "$repo/rawlogs/live_sim.ini" -o "$out/live_soak.rawlog" \
    --duration "$live_s" || rc=$?
  echo "live: exit $rc" | tee -a "$summary"
  grep -E '^(live: stopped|rawlog: |observations: |star tracker: |rawlog flushes: )|^  |frames skipped' \
    "$out/live.log" | tee -a "$summary" || true
  rss_summary live
  plot_rss live "startracker live, simulated sensors in real time, $live_s s"
fi

if [[ $do_replay == 1 ]]; then
  rl="$out/one_hour.rawlog"
  config="$repo/rawlogs/one_hour_tracker.ini"
  if [[ -n "$replay_rawlog" ]]; then
    rl=$replay_rawlog
    config=${replay_config:-${rl%.rawlog}_tracker.ini}
    [[ -f "$rl" ]] || { echo "soak.sh: --replay-rawlog '$rl': no such file" >&2; exit 2; }
    [[ -f "$config" ]] || { echo "soak.sh: replay config '$config': no such file (--replay-config)" >&2; exit 2; }
  elif [[ ! -f "$rl" ]]; then
    echo "soak: simulating $rl (36,000 frames)" | tee -a "$summary"
    "$st" simulate "$repo/rawlogs/one_hour_10hz.ini" -o "$rl" --force >"$out/simulate.log" 2>&1
  fi
  echo "soak: replay of $rl -> $out/replay.log" | tee -a "$summary"
  rc=0
  run_sampled replay "$st" replay "$rl" --config "$config" --csv "$out/replay.csv" -f || rc=$?
  echo "replay: exit $rc" | tee -a "$summary"
  grep -E 'frames|observations|solved' "$out/replay.log" | head -8 | tee -a "$summary" || true
  rss_summary replay
  plot_rss replay "startracker replay of $(basename "$rl")"
fi
echo "soak: summary in $summary; curves $out/*_rss.png"
