/// @file sky.hpp
/// What the experiments share: the star database and camera built from the options, random
/// attitudes, the catalog stars visible in the image, and simulated centroids for an error
/// situation (noise, false stars, dropped, missing and displaced stars).
#pragma once
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "app/montecarlo/mc_options.hpp"
#include "catalog/star_database.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/detect/centroid.hpp"

namespace st::app::mc {

/// Database from the options' catalog (default: the committed Hipparcos subset) at epoch
/// 2000 without aberration/parallax (the simulation is self-consistent), V <= mag_limit,
/// pairs up to `max_pair_angle`, double stars merged within options.merge_arcsec.
std::shared_ptr<const StarDatabase> buildDatabase(const McOptions& o, double max_pair_angle,
                                                  double mag_limit);

/// Square pixels, principal point at the centre, horizontal FOV o.fov_deg, o.width x o.height.
CameraModel makeCamera(const McOptions& o);

/// Uniformly distributed attitude (normalised 4-D Gaussian), canonical.
Quat randomAttitude(std::mt19937_64& rng);

struct VisibleStar {
  uint32_t star;  ///< index into db.stars()
  Vec2 px;        ///< true pixel
  double mag;
};
/// Database stars with mag <= mag_limit that project inside the image and, when
/// field_stop_rad > 0, lie within field_stop_rad / 2 of the boresight (a circular field stop,
/// McOptions::field_stop_deg), brightest first.
std::vector<VisibleStar> visibleStars(const StarDatabase& db, const CameraModel& cam,
                                      const Quat& q_ib, double mag_limit, double field_stop_rad);
/// The field stop of the options in radians (0 = none).
double fieldStop(const McOptions& o);

/// One error situation of the robustness tables (seed 003 Table 2 and sweeps around it).
struct ErrorSituation {
  std::string name;
  std::string group;     ///< "seed003", "false", "drop", "noise": which sweep it belongs to
  double sweep_x = 0;    ///< the swept value (for the plots)
  double noise_px = 0.1; ///< centroid noise, 1-sigma per axis; also the reported covariance
  int false_stars = 0;   ///< spikes at uniform random pixels and brightness ranks
  double drop_fraction = 0;  ///< each true star missing with this probability
  int missing = 0;       ///< this many more true stars removed (at random)
  int displaced = 0;     ///< true stars moved by `displace_sigma` noise sigmas ("outside the
                         ///< tolerance limits"): their covariance is not told
  double displace_sigma = 10;
};

struct Scene {
  std::vector<Centroid> centroids;  ///< brightest first
  std::vector<int> truth;           ///< database star index per centroid, -1 = false star
  int n_true = 0, n_false = 0;
};
Scene makeScene(std::mt19937_64& rng, const CameraModel& cam,
                const std::vector<VisibleStar>& visible, const ErrorSituation& sit);

}  // namespace st::app::mc
