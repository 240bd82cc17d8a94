#include "sensors/mrpt/observation_star_tracker.hpp"

#include <mrpt/math/CVectorFixed.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/stl_serialization.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>

#include "common/conventions.hpp"
#include "common/mrpt_convert.hpp"

namespace st {

IMPLEMENTS_SERIALIZABLE(CObservationStarTracker, mrpt::obs::CObservation, st)

void CObservationStarTracker::setWriteVersion(uint8_t v) {
  if (v > kCurrentVersion) {
    throw std::invalid_argument("CObservationStarTracker: no serialization version " +
                                std::to_string(v));
  }
  write_version_ = v;
}

uint8_t CObservationStarTracker::serializeGetVersion() const { return write_version_; }

namespace {
// CArchive has no operators for Eigen or CQuaternion (MRPT-NOTES.md): write the doubles.
void writeVec(mrpt::serialization::CArchive& out, const double* p, int n) {
  for (int i = 0; i < n; ++i) out << p[i];
}
void readVec(mrpt::serialization::CArchive& in, double* p, int n) {
  for (int i = 0; i < n; ++i) in >> p[i];
}
// MRPT's string layout (uint32 length, bytes) read in chunks: a damaged length then fails at
// the end of the data instead of allocating and zeroing up to 4 GB first (a fuzz finding,
// tests/fuzz/regressions/rawlog/).
void readString(mrpt::serialization::CArchive& in, std::string& s) {
  uint32_t n = 0;
  in >> n;
  s.clear();
  while (s.size() < n) {
    const std::size_t old = s.size(), chunk = std::min<std::size_t>(n - old, 1 << 16);
    s.resize(old + chunk);
    in.ReadBuffer(&s[old], chunk);
  }
}
}  // namespace

void CObservationStarTracker::serializeTo(mrpt::serialization::CArchive& out) const {
  const uint8_t version = serializeGetVersion();
  // The base class serializes none of timestamp, sensorLabel or the pose (MRPT-NOTES.md).
  out << timestamp << sensorLabel;
  // The pose as its 3x4 matrix: exact, unlike a round trip through yaw/pitch/roll.
  mrpt::math::CVectorFixedDouble<12> pose12;
  sensor_pose.getAs12Vector(pose12);
  writeVec(out, &pose12[0], 12);
  out << static_cast<uint8_t>(mode) << reason;
  // q_ib stored scalar first (w, x, y, z) as in MRPT's CQuaternion.
  out << q_ib.w() << q_ib.x() << q_ib.y() << q_ib.z();
  writeVec(out, cov_body.data(), 9);
  out << static_cast<uint32_t>(stars.size());
  for (const MatchedStar& s : stars) {
    out << s.catalog_id;
    writeVec(out, s.px.data(), 2);
    writeVec(out, s.v_cam.data(), 3);
    out << s.residual;
  }
  out << num_blobs;
  if (version >= 1) out << timings.detect << timings.identify << timings.attitude << timings.total;
  if (version >= 2) out << static_cast<uint8_t>(failure);
  if (version >= 3) {
    out << static_cast<uint8_t>(rate ? 1 : 0);
    if (rate) {
      writeVec(out, rate->rate_body.data(), 3);
      writeVec(out, rate->cov_body.data(), 9);
      out << rate->interval_s << static_cast<int32_t>(rate->stars);
    }
  }
}

void CObservationStarTracker::serializeFrom(mrpt::serialization::CArchive& in,
                                            uint8_t version) {
  switch (version) {
    case 0:
    case 1:
    case 2:
    case 3: {
      in >> timestamp;
      readString(in, sensorLabel);
      mrpt::math::CVectorFixedDouble<12> pose12;
      readVec(in, &pose12[0], 12);
      sensor_pose = mrpt::poses::CPose3D(pose12);
      uint8_t m = 0;
      in >> m;
      readString(in, reason);
      if (m > static_cast<uint8_t>(StarTrackerMode::kFailed)) {
        THROW_EXCEPTION_FMT("CObservationStarTracker: bad mode value %u", unsigned(m));
      }
      mode = static_cast<StarTrackerMode>(m);
      double w, x, y, z;
      in >> w >> x >> y >> z;
      q_ib = Quat(w, x, y, z);
      // MRPT's CQuaternion (getDescriptionAsText) refuses |q|^2 off 1 by 1e-3: so does the
      // reader, for an attitude (a fuzz finding, tests/fuzz/regressions/star_tracker_obs/).
      if (mode != StarTrackerMode::kFailed && !(std::abs(q_ib.squaredNorm() - 1.0) < 1e-3)) {
        THROW_EXCEPTION_FMT("CObservationStarTracker: attitude quaternion not normalised "
                            "(|q|^2 = %g)", q_ib.squaredNorm());
      }
      readVec(in, cov_body.data(), 9);
      uint32_t n = 0;
      in >> n;
      // Grown star by star: a damaged count ends at the end of the data, not in a huge
      // allocation (tests/fuzz/regressions/star_tracker_obs/).
      stars.clear();
      stars.reserve(std::min<uint32_t>(n, 1024));
      for (uint32_t i = 0; i < n; ++i) {
        MatchedStar s;
        in >> s.catalog_id;
        readVec(in, s.px.data(), 2);
        readVec(in, s.v_cam.data(), 3);
        in >> s.residual;
        stars.push_back(s);
      }
      in >> num_blobs;
      timings = StageTimings{};  // version 0 had no timings
      if (version >= 1) {
        in >> timings.detect >> timings.identify >> timings.attitude >> timings.total;
      }
      if (version >= 2) {
        uint8_t f = 0;
        in >> f;
        if (f > static_cast<uint8_t>(FrameFailure::kLast)) {
          THROW_EXCEPTION_FMT("CObservationStarTracker: bad failure value %u", unsigned(f));
        }
        failure = static_cast<FrameFailure>(f);
      } else {
        failure = hasAttitude() ? FrameFailure::kNone : FrameFailure::kUnknown;
      }
      rate.reset();
      if (version >= 3) {
        uint8_t has = 0;
        in >> has;
        if (has > 1) THROW_EXCEPTION_FMT("CObservationStarTracker: bad rate flag %u", unsigned(has));
        if (has) {
          MeasuredRate r;
          readVec(in, r.rate_body.data(), 3);
          readVec(in, r.cov_body.data(), 9);
          int32_t n = 0;
          in >> r.interval_s >> n;
          r.stars = n;
          rate = r;
        }
      }
      // A read object is written back in the layout it came in, so copies stay bit-exact.
      write_version_ = version;
    } break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

bool CObservationStarTracker::sameContent(const CObservationStarTracker& o) const {
  return timestamp == o.timestamp && sensorLabel == o.sensorLabel &&
         sensor_pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() ==
             o.sensor_pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() &&
         mode == o.mode && failure == o.failure && reason == o.reason &&
         q_ib.coeffs() == o.q_ib.coeffs() &&
         cov_body == o.cov_body && stars == o.stars && num_blobs == o.num_blobs &&
         timings == o.timings && rate == o.rate;
}

void CObservationStarTracker::getDescriptionAsText(std::ostream& o) const {
  CObservation::getDescriptionAsText(o);
  const auto flags = o.flags();
  const auto prec = o.precision();
  o << "Sensor pose on the vehicle (x y z yaw pitch roll [m, deg]): " << sensor_pose << "\n";
  o << "Mode: " << toString(mode) << "\n";
  if (!hasAttitude()) o << "Failure: " << toString(failure) << "\n";
  o << "Reason: " << (reason.empty() ? "(none)" : reason) << "\n";
  if (hasAttitude()) {
    o << std::setprecision(12);
    o << "q_ib (w x y z): " << q_ib.w() << " " << q_ib.x() << " " << q_ib.y() << " " << q_ib.z()
      << "  (as MRPT pose: " << toPose3DQuat(q_ib) << ")\n";
    const RaDecRoll rdr = raDecRollFromAttitude(q_ib);
    o << std::fixed << std::setprecision(6);
    o << "Boresight RA / Dec / roll [deg]: " << rad2deg(rdr.ra) << " / " << rad2deg(rdr.dec)
      << " / " << rad2deg(rdr.roll) << "\n";
    const AttitudeSigma sig = attitudeSigma(cov_body);
    o << std::setprecision(3);
    o << "1-sigma cross-boresight / roll [arcsec]: " << rad2arcsec(sig.cross_boresight) << " / "
      << rad2arcsec(sig.roll) << "\n";
    o.flags(flags);
    o << std::setprecision(6);
    o << "Covariance (body frame) [rad^2]:\n";
    for (int r = 0; r < 3; ++r) {
      o << "  " << cov_body(r, 0) << " " << cov_body(r, 1) << " " << cov_body(r, 2) << "\n";
    }
  } else {
    o << "No attitude in this frame.\n";
  }
  o.flags(flags);
  o << std::fixed << std::setprecision(3);
  o << "Detected blobs: " << num_blobs << "\n";
  o << "Timings [ms]: detect " << 1e3 * timings.detect << ", identify " << 1e3 * timings.identify
    << ", attitude " << 1e3 * timings.attitude << ", total " << 1e3 * timings.total << "\n";
  if (rate) {
    o << std::setprecision(6);
    const Vec3 sd = rate->cov_body.diagonal().cwiseMax(0.0).cwiseSqrt() * kDegPerRad;
    o << "Body rate since the previous fix [deg/s]: " << rate->rate_body.x() * kDegPerRad << " "
      << rate->rate_body.y() * kDegPerRad << " " << rate->rate_body.z() * kDegPerRad
      << "  1-sigma " << sd.x() << " " << sd.y() << " " << sd.z() << "  (" << rate->stars
      << " common stars over " << std::setprecision(3) << rate->interval_s << " s)\n";
  } else {
    o << "Body rate: none (no previous fix with common stars)\n";
  }
  o << "Matched stars: " << stars.size() << "\n";
  if (!stars.empty()) {
    o << "  catalog_id        x [px]        y [px]   v_cam (x y z)                       "
         "residual [arcsec]\n";
  }
  for (const MatchedStar& s : stars) {
    o << "  " << std::setw(10) << s.catalog_id << " " << std::setw(13) << s.px.x() << " "
      << std::setw(13) << s.px.y() << "   " << std::setprecision(8) << s.v_cam.x() << " "
      << s.v_cam.y() << " " << s.v_cam.z() << "   " << std::setprecision(3)
      << rad2arcsec(s.residual) << "\n";
  }
  o.flags(flags);
  o.precision(prec);
}

}  // namespace st
