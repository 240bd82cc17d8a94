// startracker-cli: every command (app/commands.cpp), with MRPT's rawlogs, sensors and plots,
// and every image format OpenCV reads.
#include "app/cli_main.hpp"
#include "imageio/opencv/opencv_formats.hpp"
#include "sensors/mrpt/camera_ini.hpp"

int main(int argc, char** argv) {
  st::registerIniCameraReader();           // --camera FILE.ini
  st::imageio::registerOpenCvFormats();    // BMP, WebP, ... and TIFF/PGM output
  return st::app::runCommandLine(argc, argv, st::app::addAllCommands);
}
