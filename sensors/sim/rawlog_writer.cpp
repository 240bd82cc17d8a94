#include "common/output_file.hpp"
#include "sensors/sim/rawlog_writer.hpp"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <filesystem>

#include "common/errors.hpp"
#include "common/progress.hpp"
#include "sensors/sim/sim_observations.hpp"

namespace st {

std::string externalImagesDir(const std::string& rawlog_path) {
  const std::filesystem::path p(rawlog_path);
  return (p.parent_path() / (p.stem().string() + "_Images")).string();
}

SimulateSummary simulateToRawlog(const Scenario& scenario_in, const std::string& rawlog_path,
                                 const SimulateOptions& opts) {
  Scenario sc = scenario_in;
  if (opts.frames) sc.limitFrames(*opts.frames);
  SimulateSummary sum;
  sum.seed = opts.seed.value_or(sc.seed);
  SkySimulator sim = opts.stars ? SkySimulator(sc, sum.seed, opts.stars) : SkySimulator(sc, sum.seed);
  // Further camera heads render the same sky (one star source) with their own mounting,
  // noise and faults; the gyro is the first simulator's.
  std::vector<std::unique_ptr<SkySimulator>> more_heads;
  for (int h = 1; h < static_cast<int>(sc.heads.size()); ++h)
    more_heads.push_back(std::make_unique<SkySimulator>(sc, sum.seed, sim.stars(), h));
  std::vector<const SkySimulator*> heads = {&sim};
  for (const auto& s : more_heads) heads.push_back(s.get());

  namespace fs = std::filesystem;
  if (opts.external_images) {
    sum.images_dir = externalImagesDir(rawlog_path);
    std::error_code ec;
    fs::create_directories(sum.images_dir, ec);
    if (ec) throw InputError(sum.images_dir + ": cannot create the images folder (" + ec.message() + ")");
  }
  PendingOutput out(rawlog_path);  // an interrupted run leaves no half rawlog under the name
  mrpt::io::CFileGZOutputStream file;
  if (!file.open(out.tempPath())) throw InputError(rawlog_path + ": cannot write the rawlog");
  auto ar = mrpt::serialization::archiveFrom(file);

  const int n_frames = sc.frameCount();
  ProgressBar bar("simulate", static_cast<std::size_t>(n_frames), opts.progress);
  GyroSample g;
  bool have_gyro = sim.nextGyro(g);
  VelocityStream velocity(sc);
  VelocitySample vs;
  bool have_velocity = velocity.next(vs);
  auto flush_samples_until = [&](double t) {
    // Gyro and velocity samples up to and including time t go first (a gyro interval ends by
    // then), merged in time order, the gyro's first at equal times.
    for (;;) {
      const bool g_due = have_gyro && g.t <= t + 1e-12;
      const bool v_due = have_velocity && vs.t <= t + 1e-12;
      if (g_due && (!v_due || g.t <= vs.t)) {
        ar << *makeGyroObservation(g.rate, sc.timestamp(g.t));
        ++sum.objects;
        ++sum.gyro_samples;
        have_gyro = sim.nextGyro(g);
      } else if (v_due) {
        ar << *makeVelocityObservation(vs.velocity_km_s, sc.timestamp(vs.t));
        ++sum.objects;
        ++sum.velocity_samples;
        have_velocity = velocity.next(vs);
      } else {
        break;
      }
    }
  };
  char name[160];
  for (int k = 0; k < n_frames; ++k) {
    FrameTruth truth;
    double t = 0;
    for (std::size_t h = 0; h < heads.size(); ++h) {
      const SimFrame f = heads[h]->frame(k);
      const CameraHead& head = heads[h]->head();
      if (h == 0) {
        flush_samples_until(f.t);
        t = f.t;
        truth.q_ib = f.q_ib;
      }
      for (const TrueStar& s : f.truth) truth.stars.push_back({s.id, s.px, s.mag, static_cast<int>(h)});
      // Written when the camera delivers it (after the gyro up to f.t), stamped by its clock.
      const auto stamp = sc.timestamp(f.stamp_t);
      if (f.dropped) {
        sum.frames_dropped += h == 0;
        continue;
      }
      auto cam = makeCameraObservation(f.image, sc.camera, stamp, head.label, heads[h]->mount());
      if (opts.external_images) {
        std::snprintf(name, sizeof(name), "%s_%06d.png", head.label.c_str(), k);
        const std::string file_path = (fs::path(sum.images_dir) / name).string();
        // Highest PNG compression: noisy sky frames are the bulk of a run's size.
        if (!cv::imwrite(file_path, f.image, {cv::IMWRITE_PNG_COMPRESSION, 9}))
          throw InputError(file_path + ": cannot write the image");
        cam->image.setExternalStorage(name);
      }
      ar << *cam;
      ++sum.objects;
    }
    // The truth keeps the true clock: a camera clock jump is the camera's fault alone.
    ar << *makeTruthObservation(truth, sc.timestamp(t));
    ++sum.objects;
    ++sum.frames;
    bar.update(static_cast<std::size_t>(k + 1));
  }
  flush_samples_until(sc.duration_s);
  bar.finish();
  file.close();
  out.commit();
  return sum;
}

}  // namespace st
