// Planar transforms, the static frame tree and the pose track of the bag reader.
#include "ros_frames.hpp"

#include <algorithm>
#include <cmath>

#include "freespace/errors.hpp"

namespace freespace::ros_bag {

Rigid2 Compose(const Rigid2& a, const Rigid2& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, a.yaw + b.yaw};
}

double YawOf(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

geometry_msgs::Quaternion QuaternionFromYaw(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2);
  q.w = std::cos(yaw / 2);
  return q;
}

Rigid2 RigidFromPose(double x, double y, const geometry_msgs::Quaternion& q) {
  return {x, y, YawOf(q)};
}

void FrameTree::Add(const std::string& parent, const std::string& child, const Rigid2& t) {
  parent_of_[child] = {parent, t};
}

bool FrameTree::Find(const std::string& ancestor, const std::string& child, Rigid2* out) const {
  Rigid2 acc;  // child in the current frame
  std::string frame = child;
  for (std::size_t hops = 0; hops <= parent_of_.size(); ++hops) {
    if (frame == ancestor) {
      *out = acc;
      return true;
    }
    const auto it = parent_of_.find(frame);
    if (it == parent_of_.end()) return false;
    acc = Compose(it->second.second, acc);
    frame = it->second.first;
  }
  return false;  // a loop
}

void PoseTrack::AddOdometry(double t, const std::string& child_frame, const Rigid2& pose) {
  samples_.push_back({t, pose});
  if (child_frame_.empty()) child_frame_ = child_frame;
}

void PoseTrack::AddTf(double t, const std::string& parent, const std::string& child,
                      const Rigid2& pose) {
  auto& entry = tf_[child];
  entry.first = parent;
  entry.second.push_back({t, pose});
}

std::string PoseTrack::TakeFromTf(const std::string& base_frame, const std::string& path) {
  std::string frame = base_frame;
  std::string moved;
  for (const auto& [child, entry] : tf_) moved += (moved.empty() ? "" : ", ") + child;
  if (frame.empty()) {
    if (tf_.count("base_link")) {
      frame = "base_link";
    } else if (tf_.size() == 1) {
      frame = tf_.begin()->first;
    } else {
      throw InputError(path + ": no nav_msgs/Odometry topic, and /tf moves " +
                       (moved.empty() ? std::string("no frame") : moved) +
                       ": name the vehicle frame with --base-frame");
    }
  }
  const auto it = tf_.find(frame);
  if (it == tf_.end()) {
    throw InputError(path + ": /tf never moves frame " + frame + " (it moves " +
                     (moved.empty() ? std::string("none") : moved) + ")");
  }
  samples_ = it->second.second;
  child_frame_ = frame;
  return frame;
}

void PoseTrack::Sort() {
  std::stable_sort(samples_.begin(), samples_.end(),
                   [](const Sample& a, const Sample& b) { return a.t < b.t; });
}

bool PoseTrack::At(double t, double max_gap_s, Pose2D* pose, std::string* why) const {
  if (samples_.empty()) {
    *why = "no pose sample";
    return false;
  }
  const auto after = std::lower_bound(samples_.begin(), samples_.end(), t,
                                      [](const Sample& s, double v) { return s.t < v; });
  const Sample* a = after == samples_.begin() ? &*after : &*(after - 1);
  const Sample* b = after == samples_.end() ? &samples_.back() : &*after;
  if (after != samples_.end() && after->t == t) a = b = &*after;
  const double gap = std::min(std::abs(t - a->t), std::abs(b->t - t));
  if (gap > max_gap_s) {
    *why = "the nearest pose sample is " + std::to_string(gap) + " s away (more than " +
           std::to_string(max_gap_s) + " s)";
    return false;
  }
  if (a == b || b->t <= a->t || t <= a->t || t >= b->t) {
    const Sample& s = std::abs(t - a->t) <= std::abs(b->t - t) ? *a : *b;
    *pose = {s.pose.x, s.pose.y, s.pose.yaw};
    return true;
  }
  const double f = (t - a->t) / (b->t - a->t);
  const double turn = std::remainder(b->pose.yaw - a->pose.yaw, 2 * M_PI);
  *pose = {a->pose.x + f * (b->pose.x - a->pose.x), a->pose.y + f * (b->pose.y - a->pose.y),
           a->pose.yaw + f * turn};
  return true;
}

}  // namespace freespace::ros_bag
