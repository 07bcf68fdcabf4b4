// salsa export --mcap: the run as MCAP with Foxglove's JSON schemas, so Foxglove and Lichtblick open it.
// Topics: /map (the map once, at the first frame), /targets (at the first frame and whenever one was
// found), /drones (a sphere per drone at every frame) and /drones/poses (each drone's pose at every
// frame); all in the frame "world", in the map's metres.
#include <nlohmann/json.hpp>

#include <cmath>

#include "export.hpp"
#include "mcap_writer.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::cli {
namespace {

using json = nlohmann::ordered_json;

// ---- Foxglove's schemas (foxglove/schemas, JSON Schema): the fields and types, without descriptions.

json number() { return {{"type", "number"}}; }
json integer() { return {{"type", "integer"}}; }
json string() { return {{"type", "string"}}; }
json boolean() { return {{"type", "boolean"}}; }
json array(json items) { return {{"type", "array"}, {"items", std::move(items)}}; }
/// An object whose every field is required, as in Foxglove's schemas.
json object(const char* title, json properties) {
  json required = json::array();
  for (const auto& [key, value] : properties.items()) required.push_back(key);
  return {{"title", title}, {"type", "object"}, {"properties", std::move(properties)}, {"required", std::move(required)}};
}
json time_schema(const char* title) { return object(title, {{"sec", integer()}, {"nsec", integer()}}); }
json enumeration(const char* title, std::initializer_list<const char*> names) {
  json values = json::array();
  int k = 0;
  for (const char* name : names) values.push_back({{"title", name}, {"const", k++}});
  return {{"title", title}, {"oneOf", values}};
}
json xyz(const char* title) { return object(title, {{"x", number()}, {"y", number()}, {"z", number()}}); }
json quaternion() { return object("foxglove.Quaternion", {{"x", number()}, {"y", number()}, {"z", number()}, {"w", number()}}); }
json pose() { return object("foxglove.Pose", {{"position", xyz("foxglove.Vector3")}, {"orientation", quaternion()}}); }
json color() { return object("foxglove.Color", {{"r", number()}, {"g", number()}, {"b", number()}, {"a", number()}}); }

std::string scene_update_schema() {
  const json points = array(xyz("foxglove.Point3")), colors = array(color()), indices = array(integer());
  const json entity = object(
      "foxglove.SceneEntity",
      {{"timestamp", time_schema("time")},
       {"frame_id", string()},
       {"id", string()},
       {"lifetime", time_schema("duration")},
       {"frame_locked", boolean()},
       {"metadata", array(object("foxglove.KeyValuePair", {{"key", string()}, {"value", string()}}))},
       {"arrows", array(object("foxglove.ArrowPrimitive", {{"pose", pose()},
                                                           {"shaft_length", number()},
                                                           {"shaft_diameter", number()},
                                                           {"head_length", number()},
                                                           {"head_diameter", number()},
                                                           {"color", color()}}))},
       {"cubes", array(object("foxglove.CubePrimitive", {{"pose", pose()}, {"size", xyz("foxglove.Vector3")}, {"color", color()}}))},
       {"spheres", array(object("foxglove.SpherePrimitive", {{"pose", pose()}, {"size", xyz("foxglove.Vector3")}, {"color", color()}}))},
       {"cylinders", array(object("foxglove.CylinderPrimitive", {{"pose", pose()},
                                                                 {"size", xyz("foxglove.Vector3")},
                                                                 {"bottom_scale", number()},
                                                                 {"top_scale", number()},
                                                                 {"color", color()}}))},
       {"lines", array(object("foxglove.LinePrimitive", {{"type", enumeration("foxglove.LineType", {"LINE_STRIP", "LINE_LOOP", "LINE_LIST"})},
                                                         {"pose", pose()},
                                                         {"thickness", number()},
                                                         {"scale_invariant", boolean()},
                                                         {"points", points},
                                                         {"color", color()},
                                                         {"colors", colors},
                                                         {"indices", indices}}))},
       {"triangles", array(object("foxglove.TriangleListPrimitive",
                                  {{"pose", pose()}, {"points", points}, {"color", color()}, {"colors", colors}, {"indices", indices}}))},
       {"texts", array(object("foxglove.TextPrimitive", {{"pose", pose()},
                                                         {"billboard", boolean()},
                                                         {"font_size", number()},
                                                         {"scale_invariant", boolean()},
                                                         {"color", color()},
                                                         {"text", string()}}))},
       {"models", array(object("foxglove.ModelPrimitive", {{"pose", pose()},
                                                           {"scale", xyz("foxglove.Vector3")},
                                                           {"color", color()},
                                                           {"override_color", boolean()},
                                                           {"url", string()},
                                                           {"media_type", string()},
                                                           {"data", {{"type", "string"}, {"contentEncoding", "base64"}}}}))}});
  const json deletion = object("foxglove.SceneEntityDeletion",
                               {{"timestamp", time_schema("time")}, {"type", enumeration("foxglove.SceneEntityDeletionType", {"MATCHING_ID", "ALL"})}, {"id", string()}});
  return object("foxglove.SceneUpdate", {{"deletions", array(deletion)}, {"entities", array(entity)}}).dump();
}

std::string poses_in_frame_schema() {
  return object("foxglove.PosesInFrame", {{"timestamp", time_schema("time")}, {"frame_id", string()}, {"poses", array(pose())}}).dump();
}

// ---- The messages.

/// The colours the desktop draws with (gui-qt/frame/): Okabe & Ito's set for groups, one blue for a single group.
json rgba(std::uint32_t rgb, double a = 1) {
  // Three decimals tell 8-bit channels apart (255 steps) in a third of the bytes of a full double.
  auto channel = [&](int shift) { return std::round(((rgb >> shift) & 0xFF) / 255.0 * 1000) / 1000; };
  return {{"r", channel(16)}, {"g", channel(8)}, {"b", channel(0)}, {"a", a}};
}
std::uint32_t group_rgb(std::size_t group, std::size_t groups) {
  static const std::uint32_t colours[] = {0xE69F00, 0x0072B2, 0x009E73, 0xD55E00, 0x56B4E9, 0xCC79A7, 0xF0E442};
  return groups < 2 ? 0x1f3f8c : colours[group % std::size(colours)];
}
constexpr std::uint32_t found_rgb = 0x2e9e48, unfound_rgb = 0x9a9a9a, wall_rgb = 0x3c3c3c, failed_rgb = 0x000000;

std::uint64_t nanoseconds(double t) { return static_cast<std::uint64_t>(std::llround(t * 1e9)); }
json stamp(std::uint64_t ns) { return {{"sec", ns / 1'000'000'000}, {"nsec", ns % 1'000'000'000}}; }
json point(double x, double y, double z = 0) { return {{"x", x}, {"y", y}, {"z", z}}; }
/// At (x, y, z) turned by `yaw` about z (a unit quaternion).
json pose_at(double x, double y, double yaw = 0, double z = 0) {
  return {{"position", point(x, y, z)}, {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(yaw / 2)}, {"w", std::cos(yaw / 2)}}}};
}

/// An entity in "world" holding only the given primitives (Foxglove needs every list, empty or not).
json entity(const std::string& id, std::uint64_t ns, json primitives) {
  json e = {{"timestamp", stamp(ns)}, {"frame_id", "world"}, {"id", id}, {"lifetime", stamp(0)}, {"frame_locked", false}, {"metadata", json::array()}};
  for (const char* kind : {"arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"})
    e[kind] = primitives.contains(kind) ? primitives[kind] : json::array();
  return e;
}

/// Lines in the map's walls colour: LINE_LOOP (1) for closed outlines, LINE_LIST (2) for segment pairs.
json lines(int type, json points) {
  return {{"type", type},          {"pose", pose_at(0, 0)},   {"thickness", 2.0},          {"scale_invariant", true},  // 2 px
          {"points", std::move(points)}, {"color", rgba(wall_rgb)}, {"colors", json::array()}, {"indices", json::array()}};
}

json map_update(const MapData& map, std::uint64_t ns) {
  const Rect& b = map.bounds;
  json primitives = {{"lines", json::array()}};
  primitives["lines"].push_back(lines(1, {point(b.min.x, b.min.y), point(b.max.x, b.min.y), point(b.max.x, b.max.y), point(b.min.x, b.max.y)}));
  // Every outline and wall as segments of one list: one primitive however many obstacles the map has.
  json segments = json::array();
  auto add = [&](const Polyline& p, bool closed) {
    for (std::size_t i = 0; i + 1 < p.size() + (closed ? 1 : 0); ++i) {
      const Vec2 a = p[i], c = p[(i + 1) % p.size()];
      segments.push_back(point(a.x, a.y)), segments.push_back(point(c.x, c.y));
    }
  };
  for (const Polyline& p : map.obstacles) add(p, true);
  for (const Polyline& p : map.hollow) add(p, true);
  for (const Polyline& p : map.lines) add(p, false);
  if (!segments.empty()) primitives["lines"].push_back(lines(2, std::move(segments)));
  return {{"deletions", json::array()}, {"entities", {entity("map", ns, std::move(primitives))}}};
}

}  // namespace

void export_mcap(const Recording& rec, const std::filesystem::path& file) {
  McapWriter mcap(file, "--mcap", std::string("salsa ") + salsa_version());
  const auto scene = mcap.add_schema("foxglove.SceneUpdate", "jsonschema", scene_update_schema());
  const auto poses = mcap.add_schema("foxglove.PosesInFrame", "jsonschema", poses_in_frame_schema());
  const auto map_topic = mcap.add_channel(scene, "/map", "json");
  const auto targets_topic = mcap.add_channel(scene, "/targets", "json");
  const auto drones_topic = mcap.add_channel(scene, "/drones", "json");
  const auto poses_topic = mcap.add_channel(poses, "/drones/poses", "json");

  const RecordedColumn* velocity = rec.column("velocity");
  const RecordedColumn* group = rec.column("group");
  const double target_size = 2 * (rec.target_radius > 0 ? rec.target_radius : 0.5);
  for (std::size_t f = 0; f < rec.frames(); ++f) {
    const double t = rec.times[f];
    const std::uint64_t ns = nanoseconds(t);
    if (f == 0) mcap.write(map_topic, ns, map_update(rec.map, ns).dump());

    // Targets: one flat cylinder each, in target id order, green from the time it was found; sent at
    // the first frame and at each frame where one was found since (a viewer keeps the last one sent).
    if (f == 0 || rec.found_by_time(t) != rec.found_by_time(rec.times[f - 1])) {
      json cylinders = json::array();
      for (std::size_t k = 0; k < rec.targets.size(); ++k)
        cylinders.push_back({{"pose", pose_at(rec.targets[k].x, rec.targets[k].y)},
                             {"size", point(target_size, target_size, 0.1)},
                             {"bottom_scale", 1.0},
                             {"top_scale", 1.0},
                             {"color", rgba(rec.found_time[k] <= t ? found_rgb : unfound_rgb)}});
      mcap.write(targets_topic, ns, json{{"deletions", json::array()}, {"entities", {entity("targets", ns, {{"cylinders", std::move(cylinders)}})}}}.dump());
    }

    // Drones: a sphere each, in one entity per group (replaced whole every frame, so a removed drone
    // leaves), the group's colour; a landed drone faded, a failed one black. Poses: by id, heading
    // along the velocity.
    std::vector<json> spheres(std::max<std::size_t>(rec.groups.size(), 1), json::array());
    json entities = json::array();
    json pose_list = json::array();
    for (std::size_t i = 0; i < rec.drones; ++i) {
      const Vec2 p = rec.position(f, i);
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;  // not in the run at this frame
      const double vx = velocity ? rec.at(*velocity, f, i, 0) : 0, vy = velocity ? rec.at(*velocity, f, i, 1) : 0;
      const double yaw = std::isfinite(vx) && std::isfinite(vy) && (vx != 0 || vy != 0) ? std::atan2(vy, vx) : 0;
      pose_list.push_back(pose_at(p.x, p.y, yaw));
      const double g_value = group ? rec.at(*group, f, i) : 0;
      const std::size_t g = std::isfinite(g_value) && g_value >= 0 && g_value < static_cast<double>(spheres.size()) ? static_cast<std::size_t>(g_value) : 0;
      const double size = 2 * (g < rec.groups.size() ? rec.groups[g].radius : 1);
      const std::uint8_t status = rec.status(f, i);
      spheres[g].push_back({{"pose", pose_at(p.x, p.y, 0, size / 2)},  // resting on the ground, above the targets
                            {"size", point(size, size, size)},
                            {"color", status == 2 ? rgba(failed_rgb) : rgba(group_rgb(g, rec.groups.size()), status == 1 ? 0.35 : 1)}});
    }
    for (std::size_t g = 0; g < spheres.size(); ++g)
      entities.push_back(entity("drones/" + (g < rec.groups.size() ? rec.groups[g].name : std::string("swarm")), ns, {{"spheres", std::move(spheres[g])}}));
    mcap.write(drones_topic, ns, json{{"deletions", json::array()}, {"entities", std::move(entities)}}.dump());
    mcap.write(poses_topic, ns, json{{"timestamp", stamp(ns)}, {"frame_id", "world"}, {"poses", std::move(pose_list)}}.dump());
  }
  mcap.close();
}

}  // namespace salsa::cli
