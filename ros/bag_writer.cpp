// The estimator's results into a ROS 1 bag (freespace_ros/bag.hpp): per scan the local map as a
// nav_msgs/OccupancyGrid (freespace::FillOccupancyGrid's values) and the free-space polygon as
// a geometry_msgs/PolygonStamped, both stamped with the scan's time.
#include <geometry_msgs/PolygonStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <rosbag/bag.h>

#include <algorithm>
#include <memory>

#include "freespace/errors.hpp"
#include "freespace/map_io.hpp"
#include "freespace_ros/bag.hpp"
#include "ros_frames.hpp"

// Under AddressSanitizer the bag a failed close leaves undestroyed (Abandon()) is kept on
// purpose: LeakSanitizer is told so.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FREESPACE_LSAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define FREESPACE_LSAN 1
#endif
#ifdef FREESPACE_LSAN
#include <sanitizer/lsan_interface.h>
#endif

namespace freespace::ros_bag {

class BagResultWriter::Impl {
 public:
  Impl(const std::string& path, const std::string& frame_id, const std::string& prefix)
      : path_(path),
        frame_id_(frame_id),
        map_topic_(prefix + "/map"),
        polygon_topic_(prefix + "/polygon") {
    try {
      bag_->open(path, rosbag::bagmode::Write);
    } catch (const rosbag::BagException& e) {
      Abandon();
      throw OutputError(path + ": cannot create the bag: " + e.what());
    }
  }

  ~Impl() { Abandon(); }

  void Write(const Result& r, const MapView& map) {
    if (!(r.timestamp_s >= 0)) {
      throw InputError(path_ + ": scan " + std::to_string(r.scan_index) + " at t = " +
                       std::to_string(r.timestamp_s) + " s: a ROS time cannot be negative");
    }
    const ros::Time stamp(r.timestamp_s);
    // A bag's record time must be at least ros::TIME_MIN (1 ns); the stamp stays the scan's.
    const ros::Time record = std::max(stamp, ros::TIME_MIN);
    grid_.header.stamp = stamp;
    grid_.header.frame_id = frame_id_;
    grid_.header.seq = std::uint32_t(r.scan_index);
    grid_.info.map_load_time = stamp;
    grid_.info.resolution = float(map.resolution_m);
    grid_.info.width = std::uint32_t(map.width);
    grid_.info.height = std::uint32_t(map.height);
    grid_.info.origin.position.x = map.origin.x();
    grid_.info.origin.position.y = map.origin.y();
    grid_.info.origin.orientation = QuaternionFromYaw(map.map_yaw);
    grid_.data.resize(std::size_t(map.width) * std::size_t(map.height));
    FillOccupancyGrid(map, grid_.data.data());

    polygon_.header = grid_.header;
    polygon_.polygon.points.resize(r.polygon.size());
    for (std::size_t i = 0; i < r.polygon.size(); ++i) {
      polygon_.polygon.points[i].x = float(r.polygon[i].x());
      polygon_.polygon.points[i].y = float(r.polygon[i].y());
      polygon_.polygon.points[i].z = 0.0f;
    }
    try {
      bag_->write(map_topic_, record, grid_);
      bag_->write(polygon_topic_, record, polygon_);
    } catch (const rosbag::BagException& e) {
      throw OutputError(path_ + ": write failed: " + e.what());
    }
  }

  void Close() {
    try {
      bag_->close();
    } catch (const rosbag::BagException& e) {
      throw OutputError(path_ + ": write failed: " + e.what());
    }
  }

 private:
  // Closes the bag where that can still fail quietly. A bag that failed to close (a full disk)
  // throws again from rosbag::Bag's destructor, which would end the program: it is then left
  // undestroyed, its error reported already.
  void Abandon() noexcept {
    if (bag_ == nullptr) return;
    try {
      bag_->close();
    } catch (const std::exception&) {
      [[maybe_unused]] rosbag::Bag* kept = bag_.release();
#ifdef FREESPACE_LSAN
      __lsan_ignore_object(kept);
#endif
    }
  }

  std::string path_, frame_id_, map_topic_, polygon_topic_;
  std::unique_ptr<rosbag::Bag> bag_ = std::make_unique<rosbag::Bag>();
  nav_msgs::OccupancyGrid grid_;
  geometry_msgs::PolygonStamped polygon_;
};

BagResultWriter::BagResultWriter(const std::string& path, const std::string& frame_id,
                                 const std::string& topic_prefix)
    : impl_(std::make_unique<Impl>(path, frame_id, topic_prefix)) {}
BagResultWriter::~BagResultWriter() = default;

void BagResultWriter::Write(const Result& result, const MapView& map) { impl_->Write(result, map); }

void BagResultWriter::Close() { impl_->Close(); }

}  // namespace freespace::ros_bag
