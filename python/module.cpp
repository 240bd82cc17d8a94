// The Python module `startracker` (package python/startracker, extension _startracker): the
// public API (include/startracker/startracker.hpp) for NumPy images. An image is never copied
// when NumPy's memory can be used: a cv::Mat header is laid on the array's buffer (any row
// stride; a copy only when pixels within a row are not adjacent). The GIL is released while
// a frame is solved or tracked. Results are the API's JSON objects converted to dicts, so the
// keys are `startracker solve --json`'s.
#include <cstring>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "catalog/star_database.hpp"
#include "imageio/image_file.hpp"
#include "imageio/opencv/opencv_formats.hpp"
#include "include/startracker/startracker.hpp"

namespace py = pybind11;

namespace {

py::object toPython(const nlohmann::ordered_json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(toPython(e));
      return std::move(l);
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (const auto& [k, v] : j.items()) d[py::str(k)] = toPython(v);
      return std::move(d);
    }
    default: return py::none();
  }
}

/// A header on the array's pixels (kept alive by the caller's reference during the call).
cv::Mat matView(const py::array& a) {
  if (a.ndim() != 2)
    throw st::InputError("image: a 2-D grey array is needed, got " + std::to_string(a.ndim()) +
                         " dimensions");
  int type = -1;
  if (a.dtype().is(py::dtype::of<std::uint8_t>())) type = CV_8UC1;
  if (a.dtype().is(py::dtype::of<std::uint16_t>())) type = CV_16UC1;
  if (type < 0)
    throw st::InputError("image: dtype " + std::string(py::str(a.dtype())) +
                         " is not uint8 or uint16");
  if (a.strides(1) != a.itemsize() || a.strides(0) < a.shape(1) * a.itemsize())
    throw st::InputError("image: pixels of a row must be adjacent (use numpy.ascontiguousarray)");
  return cv::Mat(int(a.shape(0)), int(a.shape(1)), type, const_cast<void*>(a.data()),
                 std::size_t(a.strides(0)));
}

st::api::SolveOptions solveOptions(std::optional<double> fov_deg, const std::string& camera,
                                   std::pair<double, double> fov_range,
                                   const std::string& algorithm, const std::string& solver,
                                   double mag_limit, std::optional<double> epoch, int max_stars,
                                   const std::string& parity, std::optional<double> ra,
                                   std::optional<double> dec, std::optional<double> radius,
                                   double cpulimit, const std::string& name, bool no_aberration,
                                   bool no_cache, std::optional<double> pixel_aspect) {
  st::api::SolveOptions o;
  o.pixel_aspect = pixel_aspect;
  o.no_aberration = no_aberration;
  o.no_cache = no_cache;
  o.fov_deg = fov_deg;
  o.camera_file = camera;
  o.fov_min_deg = fov_range.first;
  o.fov_max_deg = fov_range.second;
  o.algorithm = algorithm;
  o.solver = solver;
  o.mag_limit = mag_limit;
  o.epoch_jyear = epoch;
  o.max_stars = max_stars;
  o.parity = parity;
  o.ra_deg = ra.value_or(NAN);
  o.dec_deg = dec.value_or(NAN);
  o.radius_deg = radius.value_or(NAN);
  o.cpulimit_s = cpulimit;
  o.name = name;
  return o;
}

st::CameraModel trackerCamera(int width, int height, std::optional<double> fov_deg,
                              const std::string& camera) {
  if (!camera.empty()) {
    const st::CameraModel c = st::CameraModel::loadYaml(camera);
    if (c.width() != width || c.height() != height)
      throw st::InputError(camera + ": the camera is " + std::to_string(c.width()) + "x" +
                           std::to_string(c.height()) + ", not " + std::to_string(width) + "x" +
                           std::to_string(height));
    return c;
  }
  if (!fov_deg || !(*fov_deg > 0 && *fov_deg < 180))
    throw st::InputError("Tracker needs fov_deg in (0, 180) or camera=FILE");
  return st::CameraModel::fromFov(width, height, st::deg2rad(*fov_deg));
}

}  // namespace

PYBIND11_MODULE(_startracker, m) {
  m.doc() = "Star tracker: plate solve a NumPy image, track frame by frame (C++ core)";
  st::imageio::registerOpenCvFormats();  // read_image/solve_file take what the CLI takes
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const st::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.def("version", &st::api::version);
  m.def(
      "read_image",
      [](const std::string& path) {
        st::imageio::LoadedImage img;
        {
          py::gil_scoped_release nogil;
          img = st::imageio::loadImage(path);
        }
        const cv::Mat& m = img.image;
        py::array out = m.type() == CV_16UC1
                            ? py::array(py::dtype::of<std::uint16_t>(), {m.rows, m.cols})
                            : py::array(py::dtype::of<std::uint8_t>(), {m.rows, m.cols});
        for (int r = 0; r < m.rows; ++r)
          std::memcpy(static_cast<char*>(out.mutable_data()) + r * out.strides(0), m.ptr(r),
                      m.cols * m.elemSize());
        return out;
      },
      py::arg("path"),
      "An image file (PNG, JPEG, TIFF 8/16-bit, FITS) as a 2-D uint8/uint16 array, grey, as "
      "`startracker solve` reads it");
  m.def("data_dir", &st::api::dataDir, "Folder of the default catalog");

  py::class_<st::api::Database>(m, "Database")
      .def(py::init([](const std::string& path) {
             py::gil_scoped_release nogil;  // ~17 ms of file reading: other threads go on
             return st::api::Database::load(path);
           }),
           py::arg("path"), "Load a database file made by `startracker catalog build`")
      .def_static(
          "for_camera",
          [](int width, int height, double fov_deg, double mag_limit, std::optional<double> epoch) {
            py::gil_scoped_release nogil;
            return st::api::Database::forCamera(
                st::CameraModel::fromFov(width, height, st::deg2rad(fov_deg)), mag_limit,
                epoch.value_or(0));
          },
          py::arg("width"), py::arg("height"), py::arg("fov_deg"), py::arg("mag_limit") = 6.6,
          py::arg("epoch") = py::none(),
          "Build in memory from the default catalog for a camera (horizontal FOV)")
      .def_property_readonly("source", &st::api::Database::source)
      .def_property_readonly("num_stars",
                             [](const st::api::Database& d) { return d.stars().stars().size(); })
      .def_property_readonly("epoch",
                             [](const st::api::Database& d) { return d.stars().params().epoch_jyear; });

  auto solve_doc =
      "Lost-in-space solve; returns the dict `startracker solve --json` prints (solved or "
      "not). ValueError for bad input. An array has no date: epoch= [Julian year] gives the "
      "observation's (else the database's, else today: the result's epoch_source says which; "
      "solve_file reads DATE-OBS or the file name); no_aberration=True: astrometric ICRS.";
  m.def(
      "solve",
      [](py::array image, std::optional<double> fov_deg, const std::string& camera,
         std::pair<double, double> fov_range, const std::string& algorithm,
         const std::string& solver, double mag_limit, std::optional<double> epoch, int max_stars,
         const std::string& parity, std::optional<double> ra, std::optional<double> dec,
         std::optional<double> radius, double cpulimit, const std::string& name,
         const st::api::Database* database, bool no_aberration, bool no_cache,
         std::optional<double> pixel_aspect) {
        const cv::Mat view = matView(image);
        const auto o = solveOptions(fov_deg, camera, fov_range, algorithm, solver, mag_limit,
                                    epoch, max_stars, parity, ra, dec, radius, cpulimit, name,
                                    no_aberration, no_cache, pixel_aspect);
        st::api::SolveResult r;
        {
          py::gil_scoped_release nogil;
          r = st::api::solve(view, o, database);
        }
        return toPython(r.json);
      },
      py::arg("image"), py::arg("fov_deg") = py::none(), py::arg("camera") = "",
      py::arg("fov_range") = std::make_pair(5.0, 30.0), py::arg("algorithm") = "",
      py::arg("solver") = "", py::arg("mag_limit") = 6.6, py::arg("epoch") = py::none(),
      py::arg("max_stars") = 12, py::arg("parity") = "both", py::arg("ra") = py::none(),
      py::arg("dec") = py::none(), py::arg("radius") = py::none(), py::arg("cpulimit") = 0.0,
      py::arg("name") = "<array>", py::arg("database") = nullptr,
      py::arg("no_aberration") = false, py::arg("no_cache") = false,
      py::arg("pixel_aspect") = py::none(), solve_doc);
  m.def(
      "solve_file",
      [](const std::string& path, std::optional<double> fov_deg, const std::string& camera,
         std::pair<double, double> fov_range, const std::string& algorithm,
         const std::string& solver, double mag_limit, std::optional<double> epoch, int max_stars,
         const std::string& parity, const st::api::Database* database, bool no_aberration,
         bool no_cache, std::optional<double> pixel_aspect) {
        const auto o = solveOptions(fov_deg, camera, fov_range, algorithm, solver, mag_limit,
                                    epoch, max_stars, parity, std::nullopt, std::nullopt,
                                    std::nullopt, 0, "<memory>", no_aberration, no_cache,
                                    pixel_aspect);
        st::api::SolveResult r;
        {
          py::gil_scoped_release nogil;
          r = st::api::solveFile(path, o, database);
        }
        return toPython(r.json);
      },
      py::arg("path"), py::arg("fov_deg") = py::none(), py::arg("camera") = "",
      py::arg("fov_range") = std::make_pair(5.0, 30.0), py::arg("algorithm") = "",
      py::arg("solver") = "", py::arg("mag_limit") = 6.6, py::arg("epoch") = py::none(),
      py::arg("max_stars") = 12, py::arg("parity") = "both", py::arg("database") = nullptr,
      py::arg("no_aberration") = false, py::arg("no_cache") = false,
      py::arg("pixel_aspect") = py::none(),
      "solve() on an image file; its epoch from DATE-OBS or the file name");

  py::class_<st::api::Tracker>(m, "Tracker")
      .def(py::init([](int width, int height, std::optional<double> fov_deg,
                       const std::string& camera, std::optional<st::api::Database> database,
                       double mag_limit, std::optional<double> epoch,
                       std::optional<double> min_sigma_px, std::optional<double> tracking_min_sigma_px) {
             const st::CameraModel cam = trackerCamera(width, height, fov_deg, camera);
             st::api::TrackerSettings opts;
             if (min_sigma_px) opts.min_sigma_px = *min_sigma_px;
             if (tracking_min_sigma_px) opts.tracking_min_sigma_px = *tracking_min_sigma_px;
             py::gil_scoped_release nogil;
             if (!database) database = st::api::Database::forCamera(cam, mag_limit, epoch.value_or(0));
             return std::make_unique<st::api::Tracker>(cam, opts, database);
           }),
           py::arg("width"), py::arg("height"), py::arg("fov_deg") = py::none(),
           py::arg("camera") = "", py::arg("database") = py::none(), py::arg("mag_limit") = 6.6,
           py::arg("epoch") = py::none(), py::arg("min_sigma_px") = py::none(),
           py::arg("tracking_min_sigma_px") = py::none(),
           "A per-frame tracker for a camera (fov_deg: horizontal FOV, or camera=OpenCV YAML). "
           "min_sigma_px / tracking_min_sigma_px floor the centroid sigma of lost-in-space / "
           "tracking (TrackerSettings; an uncalibrated lens needs ~0.5 px, as solve uses)")
      .def(
          "process",
          [](st::api::Tracker& t, py::array image, double time_s,
             std::optional<std::array<double, 3>> rate) {
            const cv::Mat view = matView(image);
            st::FrameInputs in;
            if (rate) in.rate_body = st::Vec3((*rate)[0], (*rate)[1], (*rate)[2]);
            st::FrameResult r;
            {
              py::gil_scoped_release nogil;
              r = t.process(view, time_s, in);
            }
            return toPython(st::api::frameResultJson(r));
          },
          py::arg("image"), py::arg("t"), py::arg("rate") = py::none(),
          "One frame at time t [s] (increasing), with an optional body rate [rad/s] (gyro); "
          "returns the fix as a dict (mode, failure, q_ib, ra/dec/roll, covariance, stars)")
      .def("reset", &st::api::Tracker::reset);
}
