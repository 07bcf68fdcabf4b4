// The engine's snapshots: what the worker publishes for the view, the plots and the inspector.
#include <algorithm>
#include <limits>

#include "engine_worker.hpp"
#include "salsa/core/experiments/test_models.hpp"

namespace salsa::gui {

void Engine::Worker::publish_empty() {
  auto snap = std::make_shared<Snapshot>();
  snap->scene = std::make_shared<Scene>();
  snap->stats = stats;
  std::lock_guard lock(snapshot_mutex);
  published = std::move(snap);
}

std::shared_ptr<const Snapshot> Engine::Worker::make_snapshot() {
  const auto began = Clock::now();
  auto snap = std::make_shared<Snapshot>();
  snap->scene = scene;
  snap->stats = stats;
  snap->state = state;
  snap->error = error;
  snap->test_name = start.name;
  if (!sim) return snap;
  fill_snapshot(*snap, *sim, session->current().has_wind());
  snap->changes_applied = session->changes_applied();
  snap->inexact = sim->dt() != start.dt;
  snap->found = found;
  snap->targets_found = found_count;
  snap->found_version = found_version;
  if (trail_length > 0) {
    if (!trails_published) {  // oldest first: each drone's ring from its next slot on, then the rest
      auto trails = std::make_shared<std::vector<Vec2>>(trail_ring.size());
      const std::size_t first = trail_taken % trail_length;
      for (std::size_t d = 0; d < trail_ring.size() / trail_length; ++d) {
        const Vec2* ring = trail_ring.data() + d * trail_length;
        std::rotate_copy(ring, ring + first, ring + trail_length, trails->data() + d * trail_length);
      }
      trails_published = std::move(trails);
    }
    snap->trail_length = trail_length;
    snap->trails = trails_published;
  }
  snap->heat = heat;
  if (selected && *selected < snap->positions.size() && snap->status[*selected] != DroneStatus::removed) snap->selected = inspect(*selected);
  if (speed_samples.size() >= 2) {
    const auto& [w0, t0] = speed_samples.front();
    const auto& [w1, t1] = speed_samples.back();
    const double wall = seconds(w1 - w0);
    snap->speed = wall > 0 ? (t1 - t0) / wall : 0;
  }
  snap->build_ms = seconds(Clock::now() - began) * 1000;
  return snap;
}

bool Engine::Worker::fleet_on() const {
  if (session->current().fleet()) return true;
  const auto& timeline = session->timeline();
  return std::any_of(timeline.begin(), timeline.begin() + static_cast<std::ptrdiff_t>(session->changes_applied()),
                     [](const Change& c) { return c.key.starts_with("fail."); });
}

Inspection Engine::Worker::inspect(std::uint32_t id) const {
  Inspection in;
  in.id = id;
  const std::uint32_t group = sim->drone_groups()[id];
  in.group = sim->setup().groups[group].name;
  const auto p = sim->drone_positions();
  const auto status = sim->drone_status();
  in.position = p[id];
  const DroneConfig& drone = sim->drone_config(group);
  const double range = drone.detection_range;
  if (status[id] == DroneStatus::flying)  // a stopped drone sees no one, and no one sees it
    for (std::uint32_t j = 0; j < p.size(); ++j)  // one drone against all: cheap, and only for the selection
      if (j != id && status[j] == DroneStatus::flying && distance_squared(p[j], p[id]) <= range * range) in.neighbours.push_back(j);
  if (status[id] == DroneStatus::flying) {  // a stopped drone senses nothing: its last hits are stale
    const auto hits = sim->obstacle_hits(id);
    in.hits.assign(hits.begin(), hits.end());
  }
  if ((in.fleet = fleet_on())) in.status = status_name(*sim, id);
  // The test as run so far (its changes those applied): a test model of a column's model name says
  // whether that model is on (the fleet keeps its arrays in every test, a fail.* change may switch it
  // on). A model with no test model lists its columns only while it keeps them.
  TestSpec run = session->current();
  run.changes.assign(session->timeline().begin(), session->timeline().begin() + static_cast<std::ptrdiff_t>(session->changes_applied()));
  auto on = [&](std::string_view model) {
    for (const TestModel& m : test_models())
      if (m.key == model) return !m.in_use || m.in_use(run);
    return true;
  };
  for (const StateColumn& c : sim->columns()) {
    if (id >= c.rows || !c.data || !on(c.model)) continue;
    StateLine line{std::string(c.model), std::string(c.name), std::string(c.unit), {}, c.type != StateColumn::Type::f64};
    for (std::size_t k = 0; k < c.width; ++k) {
      const std::size_t at = id * c.width + k;
      switch (c.type) {
        case StateColumn::Type::f64: line.values.push_back(static_cast<const double*>(c.data)[at]); break;
        case StateColumn::Type::u32: line.values.push_back(static_cast<const std::uint32_t*>(c.data)[at]); break;
        case StateColumn::Type::u8: line.values.push_back(static_cast<const std::uint8_t*>(c.data)[at]); break;
      }
    }
    in.state.push_back(std::move(line));
  }
  if (drone.position_noise > 0) in.perceived = sim->perceived_position(id);
  if (sim->setup().comm.on) {
    in.heard.emplace();
    for (const Message& m : sim->inbox(id)) in.heard->push_back(m.sender);
    std::sort(in.heard->begin(), in.heard->end());
  }
  try {  // plugin code on the worker thread: a throw must not end the desktop
    in.memory = sim->behavior(group).inspect(id);
  } catch (const std::exception& e) {
    const PluginFailure failure("behavior", group, e.what());  // its message on one line
    in.memory = failed_plugin(failure, session->current(), *host) + " failed in inspect: " + failure.what();
  } catch (...) {
    in.memory = failed_plugin(PluginFailure("behavior", group, ""), session->current(), *host) +
                " failed in inspect: an exception that is not a std::exception";
  }
  return in;
}

void Engine::Worker::publish(bool now_all) {
  const auto now = Clock::now();
  if (sim) {
    speed_samples.emplace_back(now, sim->time());
    while (speed_samples.size() > 2 && now - speed_samples.front().first > std::chrono::seconds(1)) speed_samples.pop_front();
    if (now_all || !heat || now - heat_published > std::chrono::milliseconds(250)) publish_heat(now);
  }
  auto snap = make_snapshot();
  std::lock_guard lock(snapshot_mutex);
  published = std::move(snap);
}

void Engine::Worker::publish_heat(Clock::time_point now) {
  auto h = std::make_shared<HeatMap>(heat_grid);
  const std::uint32_t most = heat_counts.empty() ? 0 : *std::max_element(heat_counts.begin(), heat_counts.end());
  h->values.resize(heat_counts.size());
  for (std::size_t i = 0; i < heat_counts.size(); ++i)
    h->values[i] = most ? static_cast<float>(100.0 * heat_counts[i] / most) : 0.f;
  heat = std::move(h);
  heat_published = now;
}

}  // namespace salsa::gui
