// `startracker camera`: check a camera file and print its intrinsics and field of view.
#include <cstdio>

#include "app/cli/common_flags.hpp"
#include "app/camera_flags.hpp"
#include "app/cli/validators.hpp"
#include "app/command.hpp"
#include "common/output_file.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::app {

void addCameraCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand("camera", "Load a camera model and print it (checks the file)");
  auto opts = std::make_shared<solve::CameraOptions>();
  auto size = std::make_shared<std::vector<int>>();
  addCameraFlags(*cmd, *opts);
  cmd->add_option("--size", *size, "Image size W H (needed with --fov-deg)")
      ->check(cli::WholeNumber(1, 1'000'000))
      ->expected(2);
  auto out = std::make_shared<std::string>();
  cmd->add_option("--save", *out, "Write the camera as OpenCV YAML to this file");
  auto force = std::make_shared<bool>(false);
  cli::addForceFlag(*cmd, *force);
  // `camera FILE` as well as `camera --camera FILE` (issue 39: the plain form was refused).
  auto file = std::make_shared<std::string>();
  cmd->add_option("file", *file, "Camera file (the same as --camera FILE)");
  cmd->callback([=, &run] {
    if (!file->empty()) {
      if (!opts->camera_file.empty())
        throw CLI::ValidationError("camera", "give the camera file once: FILE or --camera FILE");
      opts->camera_file = *file;
    }
    run = [=] {
      const int w = size->size() == 2 ? (*size)[0] : 0, h = size->size() == 2 ? (*size)[1] : 0;
      if (opts->fov_deg > 0 && (w <= 0 || h <= 0))
        throw InputError("--fov-deg needs --size W H with positive values");
      if (!out->empty()) prepareOutputFile(*out, "--save", *force);
      const CameraModel cam = opts->resolve(w, h);
      std::printf("%s\n", cam.describe().c_str());
      std::printf("pixel scale %.3f arcsec/px, half-diagonal FOV %.4f deg\n",
                  rad2arcsec(cam.pixelScale()), rad2deg(cam.halfDiagonalFov()));
      if (!out->empty()) cam.saveYaml(*out);
      return kExitOk;
    };
  });
}

}  // namespace st::app
