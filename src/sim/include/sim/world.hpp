// The simulated world: convex obstacles with a height range and a surface that may swallow
// the laser (dark paint, glass), some of them moving along a lane, and a ray caster that
// finds every obstacle face a horizontal ray meets, nearest first.
#pragma once

#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "sim/path.hpp"

namespace freespace::sim {

// The simulator works in the plane geometry of src/geometry: its names are the simulator's.
using namespace freespace::geometry;

enum class ObstacleKind {
  kBuilding,
  kWall,  // noise barriers, fences, garden walls
  kGuardRail,
  kCar,
  kTruck,
  kPedestrian,
  kPole,  // lamp posts, signs, bollards
  kTree,
  kHedge,
};
const char* ToString(ObstacleKind kind);
// Throws std::invalid_argument for an unknown name.
ObstacleKind ObstacleKindFromString(const std::string& name);

struct Obstacle {
  ObstacleKind kind = ObstacleKind::kWall;
  // Convex, counter-clockwise. World metres for a static obstacle; the obstacle's own frame
  // (x forward) for a moving one, placed by its mover's pose.
  Polygon shape;
  double z_min_m = 0.0;  // vertical extent above the road
  double z_max_m = 1.0;
  // Diffuse reflectivity at the laser's wavelength (0.05 black paint .. 0.5 light paint,
  // leaves); with the incidence and the range it sets the echo's power (ScannerConfig).
  double reflectivity = 0.3;
  // A beam that reaches it returns nothing with this probability whatever the power: glass
  // that lets the beam through or mirrors it away.
  double no_echo_probability = 0.0;
  int mover = -1;  // index of its motion, -1 when static
};

// How a moving obstacle moves: along `lane` from arc length s0 at a constant speed; a
// negative speed drives against the lane's direction (oncoming traffic), heading that way.
struct Track {
  Path lane;
  double s0 = 0.0;
  double speed_mps = 0.0;
  Pose2D PoseAt(double t) const;
};

struct World {
  std::vector<Obstacle> obstacles;
  std::vector<Track> tracks;  // one per mover; empty when the motion is given as poses
  int movers = 0;             // number of distinct movers

  // The poses of every mover at time t (from the tracks).
  std::vector<Pose2D> MoverPoses(double t) const;
  // Every obstacle's outline in world metres, movers placed at `mover_poses`.
  std::vector<Polygon> Place(const std::vector<Pose2D>& mover_poses) const;
  // The static obstacles' outlines and the movers' outlines at `mover_poses` as polylines
  // (closed: the first vertex repeated), for drawing.
  std::vector<std::vector<Vec2>> Outlines(const std::vector<Pose2D>& mover_poses) const;
};

// A face of an obstacle met by a ray.
struct RayHit {
  double distance = 0.0;       // metres along the ray
  int obstacle = -1;           // index into World::obstacles
  double cos_incidence = 1.0;  // |cos| of the angle between the ray and the face's normal
};

// Casts horizontal rays against a world's obstacles: the static ones through a uniform grid
// of buckets, the moving ones (few) directly, after Place()-ing them for a time.
class RayCaster {
 public:
  explicit RayCaster(const World& world, double bucket_m = 4.0);

  // Puts the movers at `mover_poses` for the following casts.
  void PlaceMovers(const std::vector<Pose2D>& mover_poses);

  // Every front face (facing the ray) met within `max_range` m, nearest first, into `hits`.
  void Cast(const Vec2& origin, const Vec2& dir, double max_range, std::vector<RayHit>* hits);
  // The distance to the first face met, or `max_range` when none is met before.
  double FirstHit(const Vec2& origin, const Vec2& dir, double max_range);

 private:
  struct Edge {
    Vec2 a, b;
    Vec2 normal;  // outward unit normal
    int obstacle = -1;
  };
  void AddEdges(int obstacle, const Polygon& outline, std::vector<Edge>* edges) const;
  void TestEdge(const Edge& e, int index, const Vec2& origin, const Vec2& dir, double max_range,
                std::vector<RayHit>* hits);

  const World& world_;
  std::vector<Edge> static_edges_;
  std::vector<Edge> moving_edges_;
  double bucket_m_;
  Vec2 grid_origin_;
  int cols_ = 0, rows_ = 0;
  std::vector<std::vector<int>> buckets_;  // edge indices per bucket
  std::vector<int> stamp_;                 // last ray that tested each static edge
  int ray_ = 0;
  std::vector<RayHit> scratch_;
};

}  // namespace freespace::sim
