// PerceptionBatch: Perceptions appended as rows of flat arrays; BatchBehavior deciding one drone.
#include "salsa/core/model/batch_behavior.hpp"

namespace salsa {

namespace {

template <class Item>
void clear_rows(PerceptionBatch::Rows<Item>& rows) {
  rows.offsets.assign(1, 0);
  rows.items.clear();
}

template <class Item>
void append_row(PerceptionBatch::Rows<Item>& rows, std::span<const Item> items) {
  rows.items.insert(rows.items.end(), items.begin(), items.end());
  rows.offsets.push_back(static_cast<std::int64_t>(rows.items.size()));
}

/// `parts`' rows one after the other into `out`, each part's offsets shifted by the items before it.
template <class Item, class Member>
void join_rows(PerceptionBatch::Rows<Item>& out, std::span<const PerceptionBatch> parts, Member member) {
  clear_rows(out);
  std::size_t items = 0, rows = 0;
  for (const PerceptionBatch& p : parts) items += (p.*member).items.size(), rows += p.size();
  out.items.reserve(items);
  out.offsets.reserve(rows + 1);
  for (const PerceptionBatch& p : parts) {
    const auto& in = p.*member;
    const auto shift = static_cast<std::int64_t>(out.items.size());
    out.items.insert(out.items.end(), in.items.begin(), in.items.end());
    for (std::size_t r = 1; r < in.offsets.size(); ++r) out.offsets.push_back(in.offsets[r] + shift);
  }
}

template <class T>
void join(std::vector<T>& out, std::span<const PerceptionBatch> parts, std::vector<T> PerceptionBatch::*member) {
  out.clear();
  for (const PerceptionBatch& p : parts) out.insert(out.end(), (p.*member).begin(), (p.*member).end());
}

}  // namespace

void PerceptionBatch::clear() {
  for (auto* v : {&position, &velocity, &air_velocity, &wind}) v->clear();
  id.clear();
  battery.clear();
  clear_rows(neighbours);
  clear_rows(targets);
  clear_rows(obstacles);
  clear_rows(messages);
  payloads.clear();
  payload_offsets.assign(1, 0);
}

void PerceptionBatch::append(const Perception& me, Senses sensed) {
  group = me.group, time = me.time, dt = me.dt, base = me.base, battery_capacity = me.battery_capacity;
  drone = {me.camera_range, me.obstacle_range, me.detection_range, me.max_speed, me.max_force, me.radius, me.mass};
  senses = sensed;
  id.push_back(me.id);
  position.push_back(me.position);
  velocity.push_back(me.velocity);
  air_velocity.push_back(me.air_velocity);
  wind.push_back(me.wind);
  battery.push_back(me.battery);
  append_row(neighbours, me.neighbours);
  append_row(targets, me.targets);
  append_row(obstacles, me.obstacles);
  // The payloads are copied: a received message's span is valid during this step's decide only.
  for (const Message& m : me.messages) {
    payloads.insert(payloads.end(), m.payload.begin(), m.payload.end());
    payload_offsets.push_back(static_cast<std::int64_t>(payloads.size()));
  }
  append_row(messages, me.messages);
}

void PerceptionBatch::finish() {
  for (std::size_t m = 0; m < messages.items.size(); ++m) {
    const auto at = static_cast<std::size_t>(payload_offsets[m]);
    messages.items[m].payload = {payloads.data() + at, static_cast<std::size_t>(payload_offsets[m + 1]) - at};
  }
}

void PerceptionBatch::assign(std::span<const PerceptionBatch> parts) {
  clear();
  if (parts.empty()) return;
  const PerceptionBatch& first = parts.front();
  group = first.group, time = first.time, dt = first.dt, drone = first.drone, base = first.base;
  battery_capacity = first.battery_capacity, senses = first.senses;
  join(id, parts, &PerceptionBatch::id);
  join(position, parts, &PerceptionBatch::position);
  join(velocity, parts, &PerceptionBatch::velocity);
  join(air_velocity, parts, &PerceptionBatch::air_velocity);
  join(wind, parts, &PerceptionBatch::wind);
  join(battery, parts, &PerceptionBatch::battery);
  join_rows(neighbours, parts, &PerceptionBatch::neighbours);
  join_rows(targets, parts, &PerceptionBatch::targets);
  join_rows(obstacles, parts, &PerceptionBatch::obstacles);
  join_rows(messages, parts, &PerceptionBatch::messages);
  join(payloads, parts, &PerceptionBatch::payloads);
  for (const PerceptionBatch& p : parts) {
    const std::int64_t shift = payload_offsets.back();
    for (std::size_t m = 1; m < p.payload_offsets.size(); ++m) payload_offsets.push_back(p.payload_offsets[m] + shift);
  }
  finish();
}

Vec2 BatchBehavior::decide(const Perception& me, Rng& rng) {
  auto batch = std::make_shared<PerceptionBatch>();
  batch->append(me, senses());
  batch->finish();
  // A stream table of one: row 0 is id 0 of a one-element span.
  const std::uint32_t row0 = 0;
  BatchRng rngs({&rng, 1}, {&row0, 1});
  Outbox* const outbox = me.outbox;
  Vec2 steering;
  decide_batch(batch, rngs, BatchOutbox({&outbox, 1}, {&me.id, 1}), {&steering, 1});
  return steering;
}

}  // namespace salsa
