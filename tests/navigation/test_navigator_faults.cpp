// Navigator faults (issue 18 item 6): a camera that repeats its readout (frozen image).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <string>

#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "navigation/navigator.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/sim_observations.hpp"

namespace st {
namespace {

TEST(NavigatorFaults, FrozenImagesFailAsFrozenAndTheGyroCarriesTheFilter) {
  // 4 s of a slow turn (0.5 deg/s, 1.8 px per frame): from 1 s to 2 s the camera repeats the
  // image of 0.9 s with fresh stamps. Processed as new, each repeat would give the attitude
  // of 0.9 s at a later time (up to 0.55 deg off).
  const std::string ini =
      "[scenario]\nduration_s = 4\nframe_rate_hz = 10\nstart_time = 2025-03-20T00:00:00\n"
      "seed = 5\nmag_limit = 6.5\n[camera]\nresolution = [256 256]\nfov_deg = 20\n"
      "[sensor]\naperture_diameter_mm = 25\nexposure_s = 0.1\npsf_sigma_px = 1.0\n"
      "read_noise_e = 8\nfull_well_e = 30000\ngain_e_per_adu = 8\nbit_depth = 12\n"
      "bias_adu = 20\n[motion]\ntype = slew\nrate_deg_s = 0 0.5 0\nra_deg = 100\n"
      "dec_deg = 10\n[gyro]\nrate_hz = 100\narw_deg_rt_h = 0.15\nrrw_deg_h_rt_h = 0.5\n"
      "bias_deg_h = 0\ninitial_bias_deg_h = 3 -2 1\n[faults]\nfrozen_s = 1 2\n";
  mrpt::config::CConfigFileMemory cfg(ini);
  const Scenario sc = Scenario::fromConfig(cfg, "frozen scenario");
  DatabaseSource src;
  src.mag_limit = 6.5;
  const StarDatabase db = *makeDatabase(src, sc.camera, sc.epochJyear());
  NavigatorOptions o;
  o.pipeline.tracker.exposure_s = sc.sensor.exposure_s;
  o.pipeline.tracker.detect.gain_e_per_adu = sc.sensor.gain();
  o.pipeline.tracker.detect.read_noise_adu = sc.sensor.read_noise_e / sc.sensor.gain();
  o.fusion.filter = MekfOptions::fromDatasheet(0.15, 0.5, 5.0);
  Navigator nav(db, sc.camera, o);
  SkySimulator sim(sc, sc.seed);
  GyroSample g;
  bool have_g = sim.nextGyro(g);
  for (int k = 0; k < sc.frameCount(); ++k) {
    const SimFrame f = sim.frame(k);
    while (have_g && g.t <= f.t) {
      nav.push(makeGyroObservation(g.rate, sc.timestamp(g.t)));
      have_g = sim.nextGyro(g);
    }
    nav.push(makeCameraObservation(f.image, sc.camera, sc.timestamp(f.t)));
    nav.push(makeTruthObservation(f.q_ib, f.truth, sc.timestamp(f.t)));
  }
  nav.flush();
  EXPECT_EQ(nav.frozenFrames(), 10);
  int frozen = 0, fixes_after = 0;
  for (const NavStep& s : nav.steps()) {
    if (!s.has_frame) continue;
    const bool in_fault = s.t > 0.95 && s.t < 1.95;
    if (in_fault) {
      EXPECT_FALSE(s.fix) << s.t;
      EXPECT_NE(s.reason.find("frozen image: identical to the frame at t = 0.9"),
                std::string::npos)
          << s.t << ": " << s.reason;
      frozen += s.reason.find("frozen image") != std::string::npos;
    } else if (s.t > 1.95) {
      fixes_after += s.fix;
    }
    // The filter's estimate stays within 5 sigma + 5" of the truth (integrity_summary's
    // bound): coasting on the gyro across the frozen second.
    if (s.initialized && s.has_truth) {
      for (int i = 0; i < 3; ++i)
        EXPECT_LE(std::abs(s.error.rotvec_body(i)),
                  5 * std::sqrt(s.P_att(i, i)) + arcsec2rad(5.0))
            << s.t;
    }
  }
  EXPECT_EQ(frozen, 10);
  EXPECT_GE(fixes_after, 19);  // 2.0 .. 3.9 s: the first new image is used again
}

}  // namespace
}  // namespace st
