#include "sensors/sim/faults.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/sim/motion.hpp"
#include "sensors/sim/random_streams.hpp"


namespace st {

const SectionSchema<FaultParams>& faultParamsSchema() {
  using F = FaultParams;
  static const auto schema =
      SectionSchema<F>()
          .add("false_stars", &F::false_stars, "number of planet-like sources not in the catalog")
          .add("false_star_mag_min", &F::false_star_mag_min, "[mag] brightest false star")
          .add("false_star_mag_max", &F::false_star_mag_max, "[mag] faintest false star")
          .add("spikes_per_frame", &F::spikes_per_frame, "Poisson mean of cosmic-ray hits per frame")
          .add("spike_e_min", &F::spike_e_min, "[e-] smallest charge of a hit")
          .add("spike_e_max", &F::spike_e_max, "[e-] largest charge of a hit")
          .add("spike_length_max_px", &F::spike_length_max_px, "[px] longest hit track")
          .add("extended_objects", &F::extended_objects, "number of bright extended objects")
          .add("extended_mag", &F::extended_mag, "[mag] brightness of an extended object")
          .add("extended_sigma_px", &F::extended_sigma_px, "[px] size of an extended object")
          .add("missing_star_fraction", &F::missing_star_fraction,
               "fraction of catalog stars not rendered, 0..1")
          .add("blinding_e_px_s", &F::blinding_e_px_s, "[e-/px/s] peak stray-light rate; 0 = off")
          .add("blinding_center_px", &F::blinding_center_px, "[px] x y centre of the glow")
          .add("blinding_radius_px", &F::blinding_radius_px, "[px] radius of the glow")
          .add("blinding_start_s", &F::blinding_start_s, "[s] glow starts")
          .add("blinding_end_s", &F::blinding_end_s, "[s] glow ends")
          .add("drop_frame_probability", &F::drop_frame_probability,
               "probability that a frame is lost, 0..1")
          .add("dropout_s", &F::dropouts, "[s] t0 t1 [t0 t1 ...]: frames in [t0, t1) are lost")
          .add("frozen_s", &F::frozen,
               "[s] t0 t1 [t0 t1 ...]: frames in [t0, t1) repeat the image before t0")
          .add("camera_time_jump_s", &F::camera_time_jumps,
               "[s] t dt [t dt ...]: from t on the camera stamps frames dt later (< 0: earlier)")
          .add("gyro_stuck_axis", &F::gyro_stuck_axis,
               "gyro axis (0 1 2 = x y z) stuck at its last reading during the gyro fault; -1 = none")
          .add("gyro_noisy_axis", &F::gyro_noisy_axis,
               "gyro axis (0 1 2) with extra noise during the gyro fault; -1 = none")
          .add("gyro_noise_deg_s", &F::gyro_noise_deg_s,
               "[deg/s] 1-sigma extra white noise per sample on the noisy axis")
          .add("gyro_fault_start_s", &F::gyro_fault_start_s, "[s] stuck / noisy axis starts")
          .add("gyro_fault_end_s", &F::gyro_fault_end_s, "[s] stuck / noisy axis ends")
          .add("gyro_spikes_per_s", &F::gyro_spikes_per_s,
               "Poisson rate of single-sample gyro spikes over the run")
          .add("gyro_spike_deg_s", &F::gyro_spike_deg_s, "[deg/s] size of a gyro spike")
          .add("saa_start_s", &F::saa_start_s, "[s] start of a radiation burst (SAA pass)")
          .add("saa_end_s", &F::saa_end_s, "[s] its end (= start: none)")
          .add("saa_flux_factor", &F::saa_flux_factor,
               "radiation flux factor during the burst, >= 1");
  return schema;
}

FaultParams FaultParams::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                    const std::string& section) {
  return fromConfig(IniReader{cfg, ""}, section);
}

FaultParams FaultParams::fromConfig(const IniReader& r, const std::string& section) {
  FaultParams f;
  faultParamsSchema().read(r, section, f);
  f.validate(r.where(section));
  return f;
}

void FaultParams::validate(const std::string& where) const {
  auto bad = [&](const std::string& what) { throw InputError(where + ": " + what); };
  if (false_stars < 0) bad("false_stars must be >= 0");
  if (false_star_mag_min > false_star_mag_max) bad("false_star_mag_min > false_star_mag_max");
  if (!(spikes_per_frame >= 0)) bad("spikes_per_frame must be >= 0");
  if (!(spike_e_min >= 0 && spike_e_min <= spike_e_max)) bad("need 0 <= spike_e_min <= spike_e_max");
  if (!(spike_length_max_px >= 0)) bad("spike_length_max_px must be >= 0");
  if (extended_objects < 0) bad("extended_objects must be >= 0");
  if (!(extended_sigma_px > 0)) bad("extended_sigma_px must be > 0");
  if (!(missing_star_fraction >= 0 && missing_star_fraction <= 1))
    bad("missing_star_fraction must be in [0, 1]");
  if (!(blinding_e_px_s >= 0)) bad("blinding_e_px_s must be >= 0");
  if (!(blinding_radius_px > 0)) bad("blinding_radius_px must be > 0");
  if (!(drop_frame_probability >= 0 && drop_frame_probability <= 1))
    bad("drop_frame_probability must be in [0, 1]");
  for (const auto& d : dropouts)
    if (!(d.first <= d.second)) bad("dropout_s: each interval needs t0 <= t1");
  for (const auto& d : frozen)
    if (!(d.first <= d.second)) bad("frozen_s: each interval needs t0 <= t1");
  for (const auto& j : camera_time_jumps)
    if (!std::isfinite(j.first) || !std::isfinite(j.second)) bad("camera_time_jump_s: t dt must be finite");
  for (int axis : {gyro_stuck_axis, gyro_noisy_axis})
    if (axis < -1 || axis > 2) bad("gyro_stuck_axis / gyro_noisy_axis must be -1, 0, 1 or 2");
  if (!(gyro_noise_deg_s >= 0)) bad("gyro_noise_deg_s must be >= 0");
  if (!(gyro_fault_start_s <= gyro_fault_end_s)) bad("gyro_fault_start_s > gyro_fault_end_s");
  if (!(gyro_spikes_per_s >= 0)) bad("gyro_spikes_per_s must be >= 0");
  if (!std::isfinite(gyro_spike_deg_s)) bad("gyro_spike_deg_s must be finite");
  if (!(std::isfinite(saa_start_s) && saa_end_s >= saa_start_s && std::isfinite(saa_end_s)))
    bad("need finite saa_start_s <= saa_end_s");
  if (!(saa_flux_factor >= 1 && saa_flux_factor <= 1e6)) bad("saa_flux_factor must be in [1, 1e6]");
}

std::vector<ExtraSource> placeFalseSources(const FaultParams& f, const CameraModel& cam,
                                           const MotionProfile& motion, double duration_s,
                                           double psf_sigma_px, uint64_t seed) {
  std::mt19937_64 rng = makeRng(seed, RandomStream::kFaultLayout);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<ExtraSource> out;
  auto place = [&](double mag, double sigma) {
    const double t = u01(rng) * std::max(0.0, duration_s);
    // Keep a margin so the whole source is in the frame at that time.
    const double m = std::min(3 * sigma, 0.25 * std::min(cam.width(), cam.height()));
    const Vec2 px(m + u01(rng) * (cam.width() - 1 - 2 * m), m + u01(rng) * (cam.height() - 1 - 2 * m));
    const Vec3 u_i = motion.attitude(t).toRotationMatrix() * cam.pixelToVector(px);
    out.push_back({u_i.normalized(), mag, sigma});
  };
  for (int i = 0; i < f.false_stars; ++i)
    place(f.false_star_mag_min + u01(rng) * (f.false_star_mag_max - f.false_star_mag_min),
          psf_sigma_px);
  for (int i = 0; i < f.extended_objects; ++i) place(f.extended_mag, f.extended_sigma_px);
  return out;
}

int addSpikes(cv::Mat& electrons, const FaultParams& f, std::mt19937_64& rng) {
  if (f.spikes_per_frame <= 0) return 0;
  CV_Assert(electrons.type() == CV_64FC1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const int n = std::poisson_distribution<int>(f.spikes_per_frame)(rng);
  for (int i = 0; i < n; ++i) {
    const double x0 = u01(rng) * (electrons.cols - 1), y0 = u01(rng) * (electrons.rows - 1);
    const double ang = u01(rng) * kTwoPi, len = u01(rng) * f.spike_length_max_px;
    const double charge = f.spike_e_min + u01(rng) * (f.spike_e_max - f.spike_e_min);
    // A straight track through the silicon: the charge shared along it, one pixel wide.
    const int steps = std::max(1, static_cast<int>(std::ceil(len / 0.25)));
    for (int k = 0; k < steps; ++k) {
      const double s = steps == 1 ? 0.0 : len * k / (steps - 1);
      const int x = static_cast<int>(std::lround(x0 + s * std::cos(ang)));
      const int y = static_cast<int>(std::lround(y0 + s * std::sin(ang)));
      if (x >= 0 && y >= 0 && x < electrons.cols && y < electrons.rows)
        electrons.at<double>(y, x) += charge / steps;
    }
  }
  return n;
}

double saaFactor(const FaultParams& f, double t) {
  return t >= f.saa_start_s && t < f.saa_end_s ? f.saa_flux_factor : 1.0;
}

void addBlinding(cv::Mat& electrons, const FaultParams& f, double t, double exposure_s) {
  if (f.blinding_e_px_s <= 0 || t < f.blinding_start_s || t > f.blinding_end_s) return;
  CV_Assert(electrons.type() == CV_64FC1);
  const double peak = f.blinding_e_px_s * exposure_s, r2s = 1.0 / (f.blinding_radius_px * f.blinding_radius_px);
  for (int y = 0; y < electrons.rows; ++y) {
    double* row = electrons.ptr<double>(y);
    const double dy = y - f.blinding_center_px.y();
    for (int x = 0; x < electrons.cols; ++x) {
      const double dx = x - f.blinding_center_px.x();
      row[x] += peak / (1.0 + (dx * dx + dy * dy) * r2s);
    }
  }
}

bool isFrameDropped(const FaultParams& f, uint64_t seed, int index, double t) {
  for (const auto& d : f.dropouts)
    if (t >= d.first && t < d.second) return true;
  if (f.drop_frame_probability <= 0) return false;
  return hashToUnit(streamSeed(seed, RandomStream::kFrameDrop, static_cast<uint64_t>(index))) <
         f.drop_frame_probability;
}

int frozenImageSource(const FaultParams& f, int k, double t, double frame_rate_hz) {
  for (const auto& d : f.frozen) {
    if (t >= d.first && t < d.second) {
      // The last frame whose time is before t0: the readout that got stuck.
      const int k0 = static_cast<int>(std::ceil(d.first * frame_rate_hz - 1e-9)) - 1;
      return std::clamp(k0, 0, k);
    }
  }
  return k;
}

double cameraClock(const FaultParams& f, double t) {
  double c = t;
  for (const auto& j : f.camera_time_jumps)
    if (t >= j.first) c += j.second;
  return c;
}

void applyGyroFaults(Vec3& rate, Vec3& held, const FaultParams& f, uint64_t seed, int index,
                     double t, double rate_hz) {
  const bool in_fault = t >= f.gyro_fault_start_s && t < f.gyro_fault_end_s;
  if (f.gyro_stuck_axis >= 0) {
    if (in_fault) {
      rate(f.gyro_stuck_axis) = held(f.gyro_stuck_axis);
    } else {
      held = rate;
    }
  }
  if (f.gyro_noisy_axis >= 0 && in_fault && f.gyro_noise_deg_s > 0) {
    std::mt19937_64 rng = makeRng(seed, RandomStream::kGyroFaults, 2 * static_cast<uint64_t>(index));
    rate(f.gyro_noisy_axis) += deg2rad(f.gyro_noise_deg_s) * std::normal_distribution<double>()(rng);
  }
  if (f.gyro_spikes_per_s > 0) {
    // A spike in this sample with the probability of one in a 1/rate_hz interval.
    std::mt19937_64 rng =
        makeRng(seed, RandomStream::kGyroFaults, 2 * static_cast<uint64_t>(index) + 1);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    if (u01(rng) < 1.0 - std::exp(-f.gyro_spikes_per_s / rate_hz)) {
      const int axis = std::min(2, static_cast<int>(u01(rng) * 3));
      rate(axis) += (u01(rng) < 0.5 ? -1.0 : 1.0) * deg2rad(f.gyro_spike_deg_s);
    }
  }
}

}  // namespace st
