#pragma once
// One test folder's files, each read once, as its plots need them (test_data.cpp).
#include <QPolygonF>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "salsa/plots/results.hpp"

namespace salsa::plots {

using Points = std::vector<std::pair<double, double>>;

// ---- The map: bounds and geometry from map.json (written by the runner) or the json map's file.
struct MapShape {
  std::optional<Rect> bounds;
  std::vector<QPolygonF> solid, hollow, lines;
};

// A drone group (the fleet model): its name and its summary.csv columns, empty when absent.
struct Group {
  std::string name;
  std::vector<double> found, alive, energy;  // found: % of the targets
};

struct TestData {
  std::string name;
  MapShape map;
  Rect area;               // the map's bounds, else the extent of the data
  Rect view;               // what the map plots show: the area and a small margin
  double target_radius = 0;  // m, from config.json's target params (0: not given)
  std::vector<double> time, found, nn, coverage;  // summary.csv; nn: NaN when empty
  std::vector<double> alive, energy;              // summary.csv with the fleet model, else empty
  std::vector<std::vector<double>> messages;      // summary.csv's message counters (comm_columns) with "comm", else empty
  bool has_coverage = false;
  std::vector<Group> groups;  // in group order: summary.csv's, then any other drones.csv names
  bool drone_groups = false;  // drones.csv has the group column
  // drones.csv, by group (its index in `groups`, 0 without the column) and drone id.
  using DroneKey = std::pair<std::size_t, long>;
  std::map<DroneKey, Points> paths;
  struct Stop { double x, y; bool failed; };  // the first row a drone is landed or failed
  std::map<DroneKey, Stop> stops;
  struct Speeds { double time, mean, sd, min, max; };
  std::vector<Speeds> speeds;
  Points targets_found, targets_missed;            // targets.csv: moving targets found where found, missed where they ended
  bool by_group() const { return drone_groups && groups.size() > 1; }
};

/// The test folder's files read (drones.csv only `with_drones`); the area is the map's bounds, else the
/// extent of the data. Throws InputError.
TestData read_test(const std::filesystem::path& folder, bool with_drones);

}  // namespace salsa::plots
