#include "apps/rig_options.hpp"

#include "tristereo/status.hpp"

namespace tristereo::cli {

void add_rig_options(std::set<std::string>& values) {
  values.insert("rig");
  values.insert("rig-right");
}

const char* rig_options_help() {
  return R"(Raw cameras (docs/calibration.md, "Raw rigs"):
  --rig FILE                LEFT and RIGHT are raw (unrectified) frames of this rig: an OpenCV
                            stereoCalibrate file (M1 D1 M2 D2 R T [R1 R2 P1 P2], YAML or XML), a
                            Kalibr camchain.yaml, or the left camera's ROS camera_info or EuRoC
                            sensor.yaml; rectified with the file's R1 R2 P1 P2, else computed
                            (OpenCV's stereoRectify, alpha 0)
  --rig-right FILE2         the right camera's file of a ROS camera_info or EuRoC pair
)";
}

LoadedRig load_rig(const Args& args, int raw_width, int raw_height) {
  LoadedRig r;
  r.rig = read_rig(args.get("rig", ""), args.get("rig-right", ""));
  r.rect = rectify_rig(r.rig);
  if (raw_width != r.rig.left.width || raw_height != r.rig.left.height)
    throw Error(ErrorCode::kSizeMismatch, "--rig " + args.get("rig", "") + " is for " +
                                              std::to_string(r.rig.left.width) + "x" +
                                              std::to_string(r.rig.left.height) + " frames, the input is " +
                                              std::to_string(raw_width) + "x" + std::to_string(raw_height));
  r.maps = std::make_shared<RectifyMaps>(build_rectify_maps(r.rig, r.rect));
  return r;
}

}  // namespace tristereo::cli
