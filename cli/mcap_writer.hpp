#pragma once
// An MCAP file (https://mcap.dev/spec, format version 0) written record by record: messages in
// uncompressed chunks, each followed by its message indexes, then a summary (schemas, channels,
// statistics, chunk indexes) with summary offsets, so readers seek by time without a full pass.
// Written by hand from the public specification: Debian packages no MCAP library.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace salsa::cli {

class McapWriter {
 public:
  /// Starts `file` (written as FILE.part and renamed by close(), so an existing FILE stays whole
  /// until the new one is). Throws InputError naming `option` and the file when it cannot be written.
  McapWriter(std::filesystem::path file, std::string option, std::string_view library);
  ~McapWriter();  ///< without close(): removes the part written
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A schema (ids from 1); `encoding` e.g. "jsonschema".
  std::uint16_t add_schema(std::string_view name, std::string_view encoding, std::string_view data);
  /// A channel on `topic` (ids from 0); `encoding` of its messages, e.g. "json".
  std::uint16_t add_channel(std::uint16_t schema, std::string_view topic, std::string_view encoding);
  /// A message on `channel` logged and published at `time` (ns). Times must not decrease per channel.
  void write(std::uint16_t channel, std::uint64_t time, std::string_view data);
  /// Writes the summary and footer and renames the file into place.
  void close();

 private:
  struct Channel {
    std::uint16_t schema;
    std::string topic, encoding;
  };
  struct Schema {
    std::string name, encoding, data;
  };
  struct ChunkIndex {
    std::uint64_t start = 0, end = 0, offset = 0, length = 0, index_length = 0, size = 0;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
  };

  void flush_chunk();
  void emit(const std::string& bytes);  ///< to the file, counted and (in the data section) checksummed
  void check();

  std::filesystem::path file_, part_;
  std::string option_;
  std::ofstream out_;
  std::uint64_t offset_ = 0;
  std::uint32_t data_crc_ = 0;
  bool summary_ = false;  ///< the data section ended: bytes written now are not in its checksum
  bool done_ = false;     ///< renamed into place

  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  std::vector<std::uint64_t> channel_messages_;
  std::uint64_t messages_ = 0, first_time_ = 0, last_time_ = 0;

  // The chunk being filled: its records, the time span and, per channel, each message's time and offset.
  std::string chunk_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::vector<ChunkIndex> chunks_;
};

}  // namespace salsa::cli
