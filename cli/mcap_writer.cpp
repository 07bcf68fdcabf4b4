// The MCAP writer: records as the specification lays them out (little-endian integers, strings and
// maps prefixed by their byte length, each record an opcode and a uint64 length), checksummed with zlib.
#include "mcap_writer.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "salsa/core/files/input_error.hpp"

namespace salsa::cli {
namespace {

namespace op {
constexpr std::uint8_t header = 0x01, footer = 0x02, schema = 0x03, channel = 0x04, message = 0x05, chunk = 0x06,
                       message_index = 0x07, chunk_index = 0x08, statistics = 0x0B, summary_offset = 0x0E, data_end = 0x0F;
}
constexpr std::string_view magic("\x89MCAP0\r\n", 8);
constexpr std::size_t chunk_target = 1 << 20;  // bytes of records per chunk: a reader seeks to within 1 MiB

std::uint32_t crc32_of(std::uint32_t crc, std::string_view bytes) {
  // zlib's crc32 takes an unsigned length: feed it in pieces that fit.
  while (!bytes.empty()) {
    const std::size_t n = std::min<std::size_t>(bytes.size(), 1u << 30);
    crc = static_cast<std::uint32_t>(::crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(n)));
    bytes.remove_prefix(n);
  }
  return crc;
}

template <class T>
void put(std::string& out, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFF));
}
void put_string(std::string& out, std::string_view s) {
  put(out, static_cast<std::uint32_t>(s.size()));
  out.append(s);
}
/// A record: opcode, content length, content.
std::string record(std::uint8_t opcode, std::string_view content) {
  std::string r;
  r.reserve(9 + content.size());
  put(r, opcode);
  put(r, static_cast<std::uint64_t>(content.size()));
  r.append(content);
  return r;
}

}  // namespace

McapWriter::McapWriter(std::filesystem::path file, std::string option, std::string_view library)
    : file_(std::move(file)), part_(file_.string() + ".part"), option_(std::move(option)) {
  std::error_code ec;
  if (std::filesystem::is_directory(file_, ec))
    throw InputError(option_ + ": " + file_.string() + " is a folder (allowed: a file to write, e.g. run.mcap)");
  out_.open(part_, std::ios::binary | std::ios::trunc);
  if (!out_) throw InputError(option_ + ": cannot write " + file_.string() + " (" + std::strerror(errno) + ")");
  std::string header;
  put_string(header, "");  // profile: none of the well-known ones (ros1, ros2) fits JSON messages
  put_string(header, library);
  emit(std::string(magic) + record(op::header, header));
}

McapWriter::~McapWriter() {
  if (done_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(part_, ec);
}

void McapWriter::check() {
  if (!out_) throw InputError(option_ + ": cannot write " + file_.string() + " (" + std::strerror(errno) + ")");
}

void McapWriter::emit(const std::string& bytes) {
  out_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  check();
  if (!summary_) data_crc_ = crc32_of(data_crc_, bytes);
  offset_ += bytes.size();
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding, std::string_view data) {
  schemas_.push_back({std::string(name), std::string(encoding), std::string(data)});
  const auto id = static_cast<std::uint16_t>(schemas_.size());
  std::string r;
  put(r, id);
  put_string(r, name);
  put_string(r, encoding);
  put_string(r, data);
  chunk_ += record(op::schema, r);
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema, std::string_view topic, std::string_view encoding) {
  const auto id = static_cast<std::uint16_t>(channels_.size());
  channels_.push_back({schema, std::string(topic), std::string(encoding)});
  channel_messages_.push_back(0);
  std::string r;
  put(r, id);
  put(r, schema);
  put_string(r, topic);
  put_string(r, encoding);
  put(r, std::uint32_t{0});  // metadata: an empty map
  chunk_ += record(op::channel, r);
  return id;
}

void McapWriter::write(std::uint16_t channel, std::uint64_t time, std::string_view data) {
  const bool first_in_chunk = chunk_index_.empty();
  chunk_start_ = first_in_chunk ? time : std::min(chunk_start_, time);
  chunk_end_ = first_in_chunk ? time : std::max(chunk_end_, time);
  first_time_ = messages_ == 0 ? time : std::min(first_time_, time);
  last_time_ = messages_ == 0 ? time : std::max(last_time_, time);
  chunk_index_[channel].emplace_back(time, chunk_.size());
  std::string r;
  r.reserve(22 + data.size());
  put(r, channel);
  put(r, static_cast<std::uint32_t>(channel_messages_[channel]));  // sequence: the channel's message count
  put(r, time);  // log time
  put(r, time);  // publish time
  r.append(data);
  chunk_ += record(op::message, r);
  ++channel_messages_[channel], ++messages_;
  if (chunk_.size() >= chunk_target) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  ChunkIndex index;
  index.start = chunk_index_.empty() ? 0 : chunk_start_;
  index.end = chunk_index_.empty() ? 0 : chunk_end_;
  index.offset = offset_;
  index.size = chunk_.size();
  std::string c;
  put(c, index.start);
  put(c, index.end);
  put(c, static_cast<std::uint64_t>(chunk_.size()));  // uncompressed size
  put(c, crc32_of(0, chunk_));
  put_string(c, "");  // no compression: the JSON stays readable with a hex viewer, and zlib is not an MCAP compression
  put(c, static_cast<std::uint64_t>(chunk_.size()));
  c += chunk_;
  const std::string chunk_record = record(op::chunk, c);
  index.length = chunk_record.size();
  emit(chunk_record);
  const std::uint64_t indexes_start = offset_;
  for (const auto& [channel, entries] : chunk_index_) {
    std::string m;
    put(m, channel);
    put(m, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [time, at] : entries) put(m, time), put(m, at);
    index.index_offsets[channel] = offset_;
    emit(record(op::message_index, m));
  }
  index.index_length = offset_ - indexes_start;
  chunks_.push_back(std::move(index));
  chunk_.clear();
  chunk_index_.clear();
}

void McapWriter::close() {
  flush_chunk();
  std::string data_end;
  put(data_end, data_crc_);  // the CRC of everything before this record, magic and header included
  summary_ = true;           // from here on: the summary, checksummed on its own
  out_.write(record(op::data_end, data_end).data(), 13);
  check();
  offset_ += 13;

  // The summary, grouped by opcode, each group's place kept for its Summary Offset record.
  const std::uint64_t summary_start = offset_;
  std::string summary;
  std::vector<std::tuple<std::uint8_t, std::uint64_t, std::uint64_t>> groups;
  auto group = [&](std::uint8_t opcode, const std::string& records) {
    if (records.empty()) return;
    groups.emplace_back(opcode, summary_start + summary.size(), records.size());
    summary += records;
  };
  std::string records;
  for (std::size_t i = 0; i < schemas_.size(); ++i) {
    std::string r;
    put(r, static_cast<std::uint16_t>(i + 1));
    put_string(r, schemas_[i].name);
    put_string(r, schemas_[i].encoding);
    put_string(r, schemas_[i].data);
    records += record(op::schema, r);
  }
  group(op::schema, records);
  records.clear();
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    std::string r;
    put(r, static_cast<std::uint16_t>(i));
    put(r, channels_[i].schema);
    put_string(r, channels_[i].topic);
    put_string(r, channels_[i].encoding);
    put(r, std::uint32_t{0});
    records += record(op::channel, r);
  }
  group(op::channel, records);
  std::string stats;
  put(stats, messages_);
  put(stats, static_cast<std::uint16_t>(schemas_.size()));
  put(stats, static_cast<std::uint32_t>(channels_.size()));
  put(stats, std::uint32_t{0});  // attachments
  put(stats, std::uint32_t{0});  // metadata
  put(stats, static_cast<std::uint32_t>(chunks_.size()));
  put(stats, first_time_);
  put(stats, last_time_);
  put(stats, static_cast<std::uint32_t>(channels_.size() * 10));
  for (std::size_t i = 0; i < channels_.size(); ++i) put(stats, static_cast<std::uint16_t>(i)), put(stats, channel_messages_[i]);
  group(op::statistics, record(op::statistics, stats));
  records.clear();
  for (const ChunkIndex& c : chunks_) {
    std::string r;
    put(r, c.start);
    put(r, c.end);
    put(r, c.offset);
    put(r, c.length);
    put(r, static_cast<std::uint32_t>(c.index_offsets.size() * 10));
    for (const auto& [channel, at] : c.index_offsets) put(r, channel), put(r, at);
    put(r, c.index_length);
    put_string(r, "");
    put(r, c.size);  // compressed size: the same, uncompressed
    put(r, c.size);
    records += record(op::chunk_index, r);
  }
  group(op::chunk_index, records);

  const std::uint64_t summary_offset_start = summary_start + summary.size();
  for (const auto& [opcode, start, length] : groups) {
    std::string r;
    put(r, opcode);
    put(r, start);
    put(r, length);
    summary += record(op::summary_offset, r);
  }
  // The footer's checksum covers the summary, the summary offsets and the footer up to itself.
  std::string footer;
  put(footer, summary_start);
  put(footer, summary_offset_start);
  const std::string footer_head = record(op::footer, footer + std::string(4, '\0')).substr(0, 1 + 8 + 16);
  put(footer, crc32_of(crc32_of(0, summary), footer_head));
  summary += record(op::footer, footer);
  summary.append(magic);
  out_.write(summary.data(), static_cast<std::streamsize>(summary.size()));
  out_.close();
  check();
  std::error_code ec;
  std::filesystem::rename(part_, file_, ec);
  if (ec) throw InputError(option_ + ": cannot write " + file_.string() + " (" + ec.message() + ")");
  done_ = true;
}

}  // namespace salsa::cli
