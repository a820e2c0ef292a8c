#include <brdfbake/core/error.hpp>
#include <brdfbake/env/camera.hpp>
#include <brdfbake/io/text_io.hpp>

#include <sstream>

namespace brdfbake {

CameraFrame CameraFrame::fromYawPitch(double yawDegrees, double pitchDegrees) {
  requireField(std::isfinite(yawDegrees) && std::isfinite(pitchDegrees) && std::abs(pitchDegrees) <= 90.0, "camera",
               "yaw must be finite and pitch in [-90, 90] degrees, got yaw " + formatG(yawDegrees) + ", pitch " +
                   formatG(pitchDegrees));
  const double yaw = radians(yawDegrees), pitch = radians(pitchDegrees);
  CameraFrame frame;
  frame.forward = Vec3(std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch));
  frame.up = Vec3(-std::sin(yaw) * std::sin(pitch), std::cos(pitch), std::cos(yaw) * std::sin(pitch));
  return frame;
}

void CameraFrame::validate() const {
  constexpr double kTolerance = 1e-3;
  auto text = [](const Vec3& v) {
    std::ostringstream out;
    out.precision(6);
    out << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
    return out.str();
  };
  require(forward.allFinite() && up.allFinite(), "camera forward and up must be finite");
  require(std::abs(forward.norm() - 1.0) <= kTolerance,
          "camera forward " + text(forward) + " is not a unit vector (length " + std::to_string(forward.norm()) + ")");
  require(std::abs(up.norm() - 1.0) <= kTolerance,
          "camera up " + text(up) + " is not a unit vector (length " + std::to_string(up.norm()) + ")");
  require(std::abs(forward.dot(up)) <= kTolerance,
          "camera forward " + text(forward) + " and up " + text(up) +
              " are not perpendicular (forward.up = " + std::to_string(forward.dot(up)) + ")");
}

Mat3 CameraFrame::eyeToEnvironment() const {
  const Vec3 back = -forward.normalized();
  const Vec3 y = (up - up.dot(back) * back).normalized();
  Mat3 r;
  r.col(0) = y.cross(back), r.col(1) = y, r.col(2) = back;
  return r;
}

}  // namespace brdfbake
