// Scenario builders: see scenarios.hpp. Lengths in metres, speeds in m/s; right-hand traffic.
// Obstacle heights and surfaces (reflectivity at 905 nm): cars 0 .. 1.5 m (body and wheels),
// light paint 0.3 .. 0.6, one car in five dark 0.03 .. 0.08; buildings 0 .. 12 m, 0.3, one in
// seven with a glass front that lets 60 % of the beams through; guard rails 0 .. 0.75 m, 0.5
// (the upper layers pass over them farther than about 30 m); leaves 0.5.
#include "sim/scenarios.hpp"

#include <cmath>
#include <stdexcept>

#include "geometry/geometry.hpp"
#include "sim/random.hpp"
#include "sim/rig.hpp"

namespace freespace::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Adds a static obstacle.
void Add(World* w, ObstacleKind kind, Polygon shape, double z_min, double z_max,
         double reflectivity, double no_echo = 0.0) {
  Obstacle o;
  o.kind = kind;
  o.shape = std::move(shape);
  o.z_min_m = z_min;
  o.z_max_m = z_max;
  o.reflectivity = reflectivity;
  o.no_echo_probability = no_echo;
  w->obstacles.push_back(std::move(o));
}

// A strip along `path` between lateral offsets `right` < `left`, from s0 to s1, as a chain of
// convex quads at most `piece` long (they share their ends exactly, so no gap and no overlap).
void AddStrip(World* w, const Path& path, double s0, double s1, double right, double left,
              ObstacleKind kind, double z_min, double z_max, double reflectivity,
              double piece = 4.0) {
  const int n = std::max(1, int(std::ceil((s1 - s0) / piece)));
  for (int i = 0; i < n; ++i) {
    const double a = s0 + (s1 - s0) * i / n, b = s0 + (s1 - s0) * (i + 1) / n;
    Add(w, kind,
        {path.PointAt(a, right), path.PointAt(b, right), path.PointAt(b, left),
         path.PointAt(a, left)},
        z_min, z_max, reflectivity);
  }
}

// A car-like body: a rectangle with chamfered corners (8 vertices), centred, x forward.
Polygon Body(double length, double width, double chamfer) {
  const double hl = 0.5 * length, hw = 0.5 * width, c = chamfer;
  return {{-hl + c, -hw}, {hl - c, -hw}, {hl, -hw + c}, {hl, hw - c},
          {hl - c, hw},   {-hl + c, hw}, {-hl, hw - c}, {-hl, -hw + c}};
}

// A road vehicle: body and wheels down to the road; dark paint loses echoes with range.
struct Vehicle {
  Polygon body;  // own frame
  ObstacleKind kind = ObstacleKind::kCar;
  double z_max = 1.5;
  double reflectivity = 0.4;
};

// A random parked or moving road vehicle: mostly cars, some vans; one in five dark.
Vehicle RandomVehicle(Rng* rng) {
  Vehicle v;
  const double u = rng->Uniform();
  const bool dark = rng->Bernoulli(0.2);
  if (u < 0.85) {
    v.body = Body(rng->Uniform(4.0, 4.9), rng->Uniform(1.72, 1.9), 0.25);
    v.z_max = 1.5;
  } else {
    v.body = Body(rng->Uniform(5.0, 5.9), rng->Uniform(1.95, 2.05), 0.2);
    v.z_max = 2.4;
  }
  v.reflectivity = dark ? rng->Uniform(0.03, 0.08) : rng->Uniform(0.3, 0.6);
  return v;
}

void AddVehicle(World* w, const Vehicle& v, const Pose2D& pose) {
  Add(w, v.kind, Transform(pose, v.body), 0.0, v.z_max, v.reflectivity);
}

void AddMover(World* w, const Vehicle& v, double z_min, const Path& lane, double s0, double speed) {
  Obstacle o;
  o.kind = v.kind;
  o.shape = v.body;
  o.z_min_m = z_min;
  o.z_max_m = v.z_max;
  o.reflectivity = v.reflectivity;
  o.mover = w->movers++;
  w->obstacles.push_back(o);
  w->tracks.push_back({lane, s0, speed});
}

void AddPedestrian(World* w, Rng* rng, const Vec2& at) {
  Add(w, ObstacleKind::kPedestrian, RegularPolygon(at, rng->Uniform(0.2, 0.28), 8, rng->Uniform()),
      0.0, 1.8, rng->Uniform(0.08, 0.5));
}

void AddTree(World* w, Rng* rng, const Vec2& at) {
  Add(w, ObstacleKind::kTree, RegularPolygon(at, rng->Uniform(0.12, 0.3), 8, rng->Uniform()), 0.0,
      8.0, 0.3);
}

void AddPole(World* w, const Vec2& at, double size) {
  Add(w, ObstacleKind::kPole, Rectangle(at, size, size, 0.0), 0.0, 6.0, 0.35);
}

// ---------------------------------------------------------------------------------------
// Highway: a 3-lane carriageway (3.75 m lanes, 2.5 m hard shoulder), guard rails on both
// sides, a straight, a 900 m left curve over 30 deg and a straight; trees, bushes and a noise
// barrier beyond the right rail; a broken-down car and a warning triangle on the shoulder;
// a truck and a van in the right lane at 80 km/h, a car in the middle lane at 95 km/h; two
// oncoming cars beyond the median. The vehicle starts from standstill in the left lane,
// accelerates at 3 m/s^2 to 130 km/h and overtakes.
Scenario Highway(std::uint64_t seed) {
  Rng rng(seed, kStreamWorld);
  Scenario sc;
  sc.name = "highway";
  sc.description =
      "3-lane highway with guard rails and a 900 m curve; standstill to 130 km/h in the left "
      "lane, overtaking a truck, a van and a car; a broken-down car on the shoulder";
  World& w = sc.world;
  Path road(Pose2D{0.0, 0.0, 0.0});  // the carriageway's left edge, towards the traffic
  road.Straight(350.0).Arc(900.0, 30.0 * kDeg).Straight(550.0);
  const double end = road.length();
  const double lane = 3.75;

  // Guard rails (W-beam and posts as one 0.2 m strip), median and right side.
  AddStrip(&w, road, 0.0, end, 0.75, 0.95, ObstacleKind::kGuardRail, 0.0, 0.75, 0.5);
  AddStrip(&w, road, 0.0, end, 3.05, 3.25, ObstacleKind::kGuardRail, 0.0, 0.75, 0.5);
  AddStrip(&w, road, 0.0, end, -14.45, -14.25, ObstacleKind::kGuardRail, 0.0, 0.75, 0.5);
  // The oncoming carriageway's outer rail.
  AddStrip(&w, road, 0.0, end, 17.55, 17.75, ObstacleKind::kGuardRail, 0.0, 0.75, 0.5);

  // Beyond the right rail: a noise barrier over 300 m, elsewhere bushes and trees.
  const double barrier0 = 620.0 + rng.Uniform(-30.0, 30.0), barrier1 = barrier0 + 300.0;
  AddStrip(&w, road, barrier0, barrier1, -17.3, -17.0, ObstacleKind::kWall, 0.0, 4.0, 0.25, 6.0);
  for (double s = rng.Uniform(0.0, 10.0); s < end; s += rng.Uniform(6.0, 22.0)) {
    if (s > barrier0 - 5.0 && s < barrier1 + 5.0) continue;
    if (rng.Bernoulli(0.4)) {
      const double length = rng.Uniform(2.0, 7.0), d = -rng.Uniform(16.0, 19.0);
      AddStrip(&w, road, s, std::min(end, s + length), d - rng.Uniform(0.8, 1.6), d,
               ObstacleKind::kHedge, 0.0, rng.Uniform(0.8, 2.0), 0.5, 3.0);
      s += length;
    } else {
      AddTree(&w, &rng, road.PointAt(s, -rng.Uniform(16.0, 30.0)));
    }
  }
  // Gantry and sign posts on the right verge.
  for (double s = rng.Uniform(80.0, 150.0); s < end; s += rng.Uniform(180.0, 320.0)) {
    AddPole(&w, road.PointAt(s, -15.2), 0.3);
  }

  // A broken-down car on the hard shoulder, its warning triangle 60 m before it.
  const double breakdown = 540.0 + rng.Uniform(-40.0, 40.0);
  Vehicle broken = RandomVehicle(&rng);
  Pose2D at = road.PoseAt(breakdown);
  const Vec2 p = road.PointAt(breakdown, -12.6);
  AddVehicle(&w, broken, {p.x(), p.y(), at.yaw + rng.Uniform(-2.0, 2.0) * kDeg});
  Add(&w, ObstacleKind::kPole, RegularPolygon(road.PointAt(breakdown - 60.0, -12.0), 0.25, 3), 0.0,
      0.45, 1.0);

  // Traffic: lanes are offsets of the road; movers keep their lane at a constant speed.
  const Path lane0 = road.Offset(-0.5 * lane), lane1 = road.Offset(-1.5 * lane),
             lane2 = road.Offset(-2.5 * lane);
  Vehicle truck{Body(16.5, 2.55, 0.1), ObstacleKind::kTruck, 4.0};
  AddMover(&w, truck, 0.0, lane2, rng.Uniform(100.0, 130.0), 80.0 / 3.6);
  Vehicle van{Body(5.6, 2.0, 0.2), ObstacleKind::kCar, 2.4};
  AddMover(&w, van, 0.0, lane2, rng.Uniform(175.0, 200.0), 80.0 / 3.6);
  AddMover(&w, RandomVehicle(&rng), 0.0, lane1, rng.Uniform(60.0, 90.0), 95.0 / 3.6);
  const Path oncoming = road.Offset(4.0 + 1.5 * lane);
  for (int i = 0; i < 2; ++i) {
    AddMover(&w, RandomVehicle(&rng), 0.0, oncoming, rng.Uniform(700.0, 1300.0),
             -rng.Uniform(28.0, 36.0));
  }

  // The drive: standstill to 130 km/h at 3 m/s^2 in the left lane, then cruise.
  const Pose2D start = lane0.PoseAt(5.0);
  sc.trajectory = Trajectory(start);
  const double v = 130.0 / 3.6, length = lane0.length() - 60.0;
  std::vector<PathPiece> shape;
  // Lane 0 from s = 5 on: the same pieces, the first shortened.
  double skip = 5.0;
  for (const PathPiece& piece : lane0.pieces()) {
    if (skip >= piece.length) {
      skip -= piece.length;
      continue;
    }
    shape.push_back({piece.length - skip, piece.curvature});
    skip = 0.0;
  }
  double total = 0.0;
  for (const PathPiece& piece : shape) total += piece.length;
  shape.back().length -= total - (length - 5.0);
  total = length - 5.0;
  sc.trajectory.Drive(shape, {{0.0, 0.0}, {RampLength(0.0, v, 3.0), v}, {total, v}});
  sc.duration_s = 35.0;
  return sc;
}

// ---------------------------------------------------------------------------------------
// Urban: an east-west street (two 3.25 m lanes, parking lanes, 3.5 m sidewalks, building
// fronts) crossed at x = 130 by a north-south street of the same profile. The vehicle starts
// from standstill at x = 5, reaches 50 km/h, stops before the crosswalk, waits, turns right
// into the cross street and accelerates to 40 km/h.
void BuildingRow(World* w, Rng* rng, double x0, double x1, double front, double side) {
  // Along x when `side` is +-1 (north / south of a street whose fronts are at |y| = front).
  double x = x0;
  while (x < x1 - 3.0) {
    const double length = std::min(rng->Uniform(8.0, 30.0), x1 - x);
    const double setback = rng->Bernoulli(0.5) ? 0.0 : rng->Uniform(0.3, 1.5);
    const double y0 = side * (front + setback), y1 = side * (front + 12.0);
    const double glass = rng->Bernoulli(0.15) ? 0.6 : 0.0;
    Add(w, ObstacleKind::kBuilding, Box(x, std::min(y0, y1), x + length, std::max(y0, y1)), 0.0,
        12.0, 0.3, glass);
    x += length;
    if (rng->Bernoulli(0.35)) x += rng->Uniform(2.0, 6.0);  // a driveway or an alley
  }
}

// The same for a street along y (fronts at |x - centre| = front).
void BuildingColumn(World* w, Rng* rng, double y0, double y1, double centre, double front,
                    double side) {
  double y = y0;
  while (y < y1 - 3.0) {
    const double length = std::min(rng->Uniform(8.0, 30.0), y1 - y);
    const double setback = rng->Bernoulli(0.5) ? 0.0 : rng->Uniform(0.3, 1.5);
    const double xa = centre + side * (front + setback), xb = centre + side * (front + 12.0);
    const double glass = rng->Bernoulli(0.15) ? 0.6 : 0.0;
    Add(w, ObstacleKind::kBuilding, Box(std::min(xa, xb), y, std::max(xa, xb), y + length), 0.0,
        12.0, 0.3, glass);
    y += length;
    if (rng->Bernoulli(0.35)) y += rng->Uniform(2.0, 6.0);
  }
}

// Parked cars along a line from `a` towards `b` (unit direction), centred `lateral` off it.
void ParkingLane(World* w, Rng* rng, const Vec2& a, const Vec2& b) {
  const Vec2 along = (b - a).normalized();
  const double heading = std::atan2(along.y(), along.x());
  const double total = (b - a).norm();
  double s = rng->Uniform(0.0, 3.0);
  while (true) {
    if (rng->Bernoulli(0.25)) s += rng->Uniform(5.0, 12.0);  // a free space
    const Vehicle v = RandomVehicle(rng);
    const double length = v.body[2].x() - v.body[6].x();
    if (s + length > total) break;
    const Vec2 c = a + along * (s + 0.5 * length);
    const Vec2 normal(-along.y(), along.x());
    const Vec2 centre = c + normal * rng->Uniform(-0.15, 0.15);
    AddVehicle(w, v, {centre.x(), centre.y(), heading + rng->Normal(0.0, 1.0) * kDeg});
    s += length + rng->Uniform(0.7, 2.5);
  }
}

Scenario Urban(std::uint64_t seed) {
  Rng rng(seed, kStreamWorld);
  Scenario sc;
  sc.name = "urban";
  sc.description =
      "urban street with building fronts, parked cars, trees, poles and pedestrians; 0 to "
      "50 km/h, a stop before an intersection and a right turn into the cross street";
  World& w = sc.world;
  const double cx = 130.0;       // the cross street's centre line
  const double front = 9.0;      // building fronts, from a street's centre line
  const double parking = 4.375;  // parking lane centre
  const double x_min = -60.0, x_max = 260.0, y_min = -220.0, y_max = 120.0;

  // Building fronts: the main street (y = 0) and the cross street (x = 130).
  BuildingRow(&w, &rng, x_min, cx - front, front, 1.0);
  BuildingRow(&w, &rng, x_min, cx - front, front, -1.0);
  BuildingRow(&w, &rng, cx + front, x_max, front, 1.0);
  BuildingRow(&w, &rng, cx + front, x_max, front, -1.0);
  // The corner blocks belong to the main street's rows (12 m deep): the columns start beyond.
  const double corner = front + 12.0;
  BuildingColumn(&w, &rng, y_min, -corner, cx, front, -1.0);
  BuildingColumn(&w, &rng, y_min, -corner, cx, front, 1.0);
  BuildingColumn(&w, &rng, corner, y_max, cx, front, -1.0);
  BuildingColumn(&w, &rng, corner, y_max, cx, front, 1.0);

  // Parked cars, none within 12 m of the intersection.
  const double gap = front + 3.0;
  ParkingLane(&w, &rng, {x_min, -parking}, {cx - gap, -parking});
  ParkingLane(&w, &rng, {x_min, parking}, {cx - gap, parking});
  ParkingLane(&w, &rng, {cx + gap, -parking}, {x_max, -parking});
  ParkingLane(&w, &rng, {cx + gap, parking}, {x_max, parking});
  ParkingLane(&w, &rng, {cx - parking, y_min}, {cx - parking, -gap});
  ParkingLane(&w, &rng, {cx + parking, y_min}, {cx + parking, -gap});
  ParkingLane(&w, &rng, {cx - parking, gap}, {cx - parking, y_max});
  ParkingLane(&w, &rng, {cx + parking, gap}, {cx + parking, y_max});

  // Sidewalks: trees and lamp posts at the curb, pedestrians anywhere on them.
  auto sidewalk_x = [&](double x0, double x1, double side) {
    for (double x = x0 + rng.Uniform(2.0, 10.0); x < x1 - 2.0; x += rng.Uniform(12.0, 22.0)) {
      AddTree(&w, &rng, {x, side * 6.3});
    }
    for (double x = x0 + rng.Uniform(2.0, 20.0); x < x1 - 2.0; x += rng.Uniform(22.0, 30.0)) {
      AddPole(&w, {x, side * 5.85}, 0.2);
    }
    for (double x = x0 + rng.Uniform(5.0, 25.0); x < x1 - 2.0; x += rng.Uniform(15.0, 45.0)) {
      AddPedestrian(&w, &rng, {x, side * rng.Uniform(6.9, 8.4)});
    }
  };
  auto sidewalk_y = [&](double y0, double y1, double side) {
    for (double y = y0 + rng.Uniform(2.0, 10.0); y < y1 - 2.0; y += rng.Uniform(12.0, 22.0)) {
      AddTree(&w, &rng, {cx + side * 6.3, y});
    }
    for (double y = y0 + rng.Uniform(2.0, 20.0); y < y1 - 2.0; y += rng.Uniform(22.0, 30.0)) {
      AddPole(&w, {cx + side * 5.85, y}, 0.2);
    }
    for (double y = y0 + rng.Uniform(5.0, 25.0); y < y1 - 2.0; y += rng.Uniform(15.0, 45.0)) {
      AddPedestrian(&w, &rng, {cx + side * rng.Uniform(6.9, 8.4), y});
    }
  };
  sidewalk_x(x_min, cx - gap, 1.0);
  sidewalk_x(x_min, cx - gap, -1.0);
  sidewalk_x(cx + gap, x_max, 1.0);
  sidewalk_x(cx + gap, x_max, -1.0);
  sidewalk_y(y_min, -gap, 1.0);
  sidewalk_y(y_min, -gap, -1.0);
  sidewalk_y(gap, y_max, 1.0);
  sidewalk_y(gap, y_max, -1.0);
  // People waiting at the corners and traffic-light posts.
  for (const Vec2& corner :
       {Vec2(cx - 7.2, -7.0), Vec2(cx + 7.4, 7.1), Vec2(cx + 7.0, -7.6), Vec2(cx - 7.5, 7.3)}) {
    AddPedestrian(&w, &rng, corner + Vec2(rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5)));
  }
  for (const Vec2& post :
       {Vec2(cx - 6.0, -6.0), Vec2(cx + 6.0, 6.0), Vec2(cx + 6.0, -6.0), Vec2(cx - 6.0, 6.0)}) {
    AddPole(&w, post, 0.2);
  }

  // The drive: start at x = 5 in the eastbound lane (y = -1.625).
  const double lane = -1.625, v_city = 50.0 / 3.6, v_turn = 4.0, v_cross = 40.0 / 3.6;
  const double stop_x = 112.0;  // rear axle; the front bumper stops 4.6 m before the crosswalk
  sc.trajectory = Trajectory(Pose2D{5.0, lane, 0.0});
  const double run = stop_x - 5.0;
  sc.trajectory.Drive({{run, 0.0}}, {{0.0, 0.0},
                                     {RampLength(0.0, v_city, 2.0), v_city},
                                     {run - RampLength(v_city, 0.0, 2.5), v_city},
                                     {run, 0.0}});
  sc.trajectory.Wait(3.0);
  const double radius = 7.0;
  const double approach = (cx - 1.625) - radius - stop_x;
  const double arc = radius * 0.5 * M_PI;
  const double south = 160.0;
  sc.trajectory.Drive({{approach, 0.0}, {arc, -1.0 / radius}, {south, 0.0}},
                      {{0.0, 0.0},
                       {RampLength(0.0, v_turn, 1.2), v_turn},
                       {approach + arc, v_turn},
                       {approach + arc + RampLength(v_turn, v_cross, 1.5), v_cross},
                       {approach + arc + south, v_cross}});
  sc.duration_s = 32.0;
  return sc;
}

// Takes out of the world the static obstacles [first, end) that the car's body, grown by
// `clearance_m`, would touch anywhere along the drive (sampled every 0.05 s): a long van parked
// in a bay reaches into the aisle, and the car would drive through it.
void KeepTheDriveClear(Scenario* sc, std::size_t first, std::size_t end, double clearance_m) {
  const geometry::Polygon body = VehicleBody(clearance_m);
  std::vector<geometry::Polygon> swept;
  for (double t = 0.0; t <= sc->trajectory.duration(); t += 0.05) {
    swept.push_back(Transform(sc->trajectory.At(t).pose, body));
  }
  std::vector<Obstacle>& obstacles = sc->world.obstacles;
  const auto touches = [&](const Obstacle& o) {
    for (const geometry::Polygon& at : swept) {
      if (std::abs(geometry::SignedArea(geometry::ClipToConvex(o.shape, at))) > 0.0) return true;
    }
    return false;
  };
  std::size_t kept = first;
  for (std::size_t i = first; i < end; ++i) {
    if (!touches(obstacles[i])) obstacles[kept++] = obstacles[i];
  }
  obstacles.erase(obstacles.begin() + std::ptrdiff_t(kept),
                  obstacles.begin() + std::ptrdiff_t(end));
}

// ---------------------------------------------------------------------------------------
// Parking lot: 66 x 41 m between a hedge (south), a wall (west) and a store (north), open to
// the east. Rows of 2.5 m x 5 m bays: A along the hedge, B and C back to back, D; aisles of
// 7 m between them; lamp posts between B and C; people on the walkway before the store. The
// vehicle comes in along aisle 1 from the east, stops past an empty bay of row A, reverses
// into it, waits and drives out to the east.
Scenario Parking(std::uint64_t seed) {
  Rng rng(seed, kStreamWorld);
  Scenario sc;
  sc.name = "parking";
  sc.description =
      "parking lot with four rows of bays; in along an aisle at 15 km/h, reversing into a bay, "
      "out again to the east";
  World& w = sc.world;
  AddStrip(&w, Path(Pose2D{0.0, -0.5, 0.0}).Straight(66.0), 0.0, 66.0, -0.5, 0.5,
           ObstacleKind::kHedge, 0.0, 1.6, 0.5, 3.0);
  Add(&w, ObstacleKind::kWall, Box(-1.0, 0.0, 0.0, 41.0), 0.0, 2.0, 0.25);
  // The store: a concrete front with glass doors in the middle.
  Add(&w, ObstacleKind::kBuilding, Box(-1.0, 41.0, 24.0, 56.0), 0.0, 8.0, 0.3);
  Add(&w, ObstacleKind::kBuilding, Box(24.0, 41.0, 36.0, 56.0), 0.0, 8.0, 0.3, 0.6);
  Add(&w, ObstacleKind::kBuilding, Box(36.0, 41.0, 70.0, 56.0), 0.0, 8.0, 0.3);

  const double bay_w = 2.5, x_first = 4.0;
  const int bays = 24;
  const int target = 9;  // the empty bay of row A the vehicle reverses into
  // Rows: the bay band [y0, y0 + 5]; cars face `nose` (+1: +y).
  struct Row {
    double y0;
    int nose;
  };
  const Row rows[] = {{1.0, -1}, {13.0, 1}, {18.0, -1}, {30.0, 1}};
  const std::size_t parked_begin = w.obstacles.size();
  const int island = 12;  // rows B and C keep bay 12 for a lamp post island
  for (int r = 0; r < 4; ++r) {
    for (int b = 0; b < bays; ++b) {
      if (r == 0 && b == target) continue;
      if ((r == 1 || r == 2) && b == island) continue;
      if (r == 3 && b < 2) continue;  // the trolley shelter
      if (!rng.Bernoulli(0.75)) continue;
      const Vehicle v = RandomVehicle(&rng);
      const double length = v.body[2].x() - v.body[6].x();
      const double x = x_first + bay_w * (b + 0.5) + rng.Uniform(-0.15, 0.15);
      const int nose = rng.Bernoulli(0.8) ? rows[r].nose : -rows[r].nose;
      // Parked against the bay's far end (towards the nose), 0.2 .. 0.6 m from it.
      const double far = nose > 0 ? rows[r].y0 + 5.0 : rows[r].y0;
      const double y = far - nose * (0.5 * length + rng.Uniform(0.2, 0.6));
      AddVehicle(&w, v, {x, y, nose * 0.5 * M_PI + rng.Uniform(-3.0, 3.0) * kDeg});
    }
  }
  const std::size_t parked_end = w.obstacles.size();
  for (const double x : {2.0, x_first + bay_w * (island + 0.5), 65.5}) AddPole(&w, {x, 18.0}, 0.3);
  for (int i = 0; i < 5; ++i) {
    AddPedestrian(&w, &rng, {rng.Uniform(3.0, 63.0), rng.Uniform(36.5, 40.0)});
  }
  AddPedestrian(&w, &rng, {rng.Uniform(40.0, 60.0), rng.Uniform(24.5, 28.5)});  // in aisle 2
  // A trolley shelter in row D's west end.
  Add(&w, ObstacleKind::kWall, Box(4.5, 30.5, 8.5, 33.0), 0.0, 2.2, 0.3, 0.3);

  // The drive. Aisle 1 spans y 6 .. 13; in at y = 10.8 heading west.
  const double xb = x_first + bay_w * (target + 0.5);
  const double radius = 5.5, aisle_y = 10.8;
  const double x_stop = xb - radius, x_start = 62.0;
  sc.trajectory = Trajectory(Pose2D{x_start, aisle_y, M_PI});
  const double in = x_start - x_stop;
  const double v_in = 15.0 / 3.6, v_slow = 1.5;
  sc.trajectory.Drive({{in, 0.0}}, {{0.0, 0.0},
                                    {RampLength(0.0, v_in, 1.5), v_in},
                                    {in - 8.0, v_in},
                                    {in - 2.0, v_slow},
                                    {in, 0.0}});
  sc.trajectory.Wait(1.5);
  // Reversing: the travel direction turns from east to south (clockwise) into the bay.
  const double arc = radius * 0.5 * M_PI;
  const double back = (aisle_y - radius) - 2.3;  // rear axle ends 1.3 m off the hedge side
  const double v_rev = 1.2;
  sc.trajectory.Drive({{arc, -1.0 / radius}, {back, 0.0}},
                      {{0.0, 0.0},
                       {RampLength(0.0, v_rev, 0.8), v_rev},
                       {arc + back - 1.0, v_rev},
                       {arc + back, 0.0}},
                      /*reverse=*/true);
  sc.trajectory.Wait(2.0);
  // Out: north out of the bay, a right turn to the east, then along the aisle.
  const double out = 25.0;
  sc.trajectory.Drive({{back, 0.0}, {arc, -1.0 / radius}, {out, 0.0}},
                      {{0.0, 0.0},
                       {RampLength(0.0, 2.0, 1.0), 2.0},
                       {back + arc, 2.0},
                       {back + arc + RampLength(2.0, v_in, 1.2), v_in},
                       {back + arc + out, v_in}});
  sc.duration_s = sc.trajectory.duration();
  KeepTheDriveClear(&sc, parked_begin, parked_end, 0.3);
  return sc;
}

}  // namespace

const std::vector<std::string>& ScenarioNames() {
  static const std::vector<std::string> names = {"urban", "highway", "parking"};
  return names;
}

Scenario BuildScenario(const std::string& name, std::uint64_t seed) {
  if (name == "urban") return Urban(seed);
  if (name == "highway") return Highway(seed);
  if (name == "parking") return Parking(seed);
  throw std::invalid_argument("unknown scenario '" + name + "' (urban, highway or parking)");
}

}  // namespace freespace::sim
