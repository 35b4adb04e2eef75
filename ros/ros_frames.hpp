// Planar transforms from ROS messages and the two things the bag reader builds from them: the
// static frame tree (/tf_static) and the vehicle's pose track (Odometry or /tf), interpolated
// at a scan's stamp.
#pragma once

#include <geometry_msgs/Quaternion.h>

#include <map>
#include <string>
#include <vector>

#include "freespace/types.hpp"

namespace freespace::ros_bag {

// A planar rigid transform: a child frame's origin and heading in its parent frame.
struct Rigid2 {
  double x = 0.0, y = 0.0, yaw = 0.0;
};
Rigid2 Compose(const Rigid2& parent_from_mid, const Rigid2& mid_from_child);
// The yaw of a quaternion (rotation about z; roll and pitch are ignored).
double YawOf(const geometry_msgs::Quaternion& q);
geometry_msgs::Quaternion QuaternionFromYaw(double yaw);
Rigid2 RigidFromPose(double x, double y, const geometry_msgs::Quaternion& q);

// Static transforms, child -> (parent, transform).
class FrameTree {
 public:
  void Add(const std::string& parent, const std::string& child, const Rigid2& t);
  // The transform of `child` in `ancestor`, following parents up from `child`; false when
  // `ancestor` is not above it.
  bool Find(const std::string& ancestor, const std::string& child, Rigid2* out) const;

 private:
  std::map<std::string, std::pair<std::string, Rigid2>> parent_of_;
};

// Pose samples of the vehicle frame, sorted by time.
class PoseTrack {
 public:
  void AddOdometry(double t, const std::string& child_frame, const Rigid2& pose);
  void AddTf(double t, const std::string& parent, const std::string& child, const Rigid2& pose);
  // Keeps the /tf samples of `base_frame` (empty: "base_link" when /tf moves it, else the one
  // frame /tf moves) as the track; returns the frame. Throws InputError naming the frames.
  std::string TakeFromTf(const std::string& base_frame, const std::string& path);
  void Sort();

  // The pose at `t`: interpolated between the samples around it (x, y linearly, yaw the
  // shorter way), or the nearest sample when `t` is outside the track. False (with why) when
  // the nearest sample is more than `max_gap_s` away.
  bool At(double t, double max_gap_s, Pose2D* pose, std::string* why) const;

  bool empty() const { return samples_.empty(); }
  const std::string& child_frame() const { return child_frame_; }

 private:
  struct Sample {
    double t;
    Rigid2 pose;
  };
  std::vector<Sample> samples_;
  std::string child_frame_;
  std::map<std::string, std::pair<std::string, std::vector<Sample>>> tf_;  // child -> parent
};

}  // namespace freespace::ros_bag
