#pragma once
// Strict JSON reading, shared by the core and the json map plugin: header-only, nlohmann only, never
// installed (the public SDK exposes no JSON types). On top of nlohmann's parser it refuses what the
// parser lets through or reports unclearly, each as one line "WHERE: [line L, column C: ]what (allowed)":
// nesting deeper than max_depth, duplicate keys, numbers that overflow a double, NaN and Infinity,
// text that is not UTF-8, empty and oversized files, folders. It also shows values and user text in
// messages with a bound, so no value is too deep or too large to quote.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_set>
#include <vector>

namespace salsa::strict_json {

/// Deepest nesting of arrays and objects accepted (salsa's files need 5).
inline constexpr std::size_t max_depth = 64;
/// Largest file read: far above any real test, queue, map or drone configuration file, and small
/// enough that its values fit in memory.
inline constexpr std::uintmax_t max_file_bytes = std::uintmax_t{64} << 20;

/// One line: where, what, what is allowed.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The length of the valid UTF-8 sequence `text` starts with (2 to 4 bytes, not overlong, no
/// surrogates, at most U+10FFFF), or 0.
inline std::size_t utf8_length(std::string_view text) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = b(0);
  const std::size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
  if (n == 0 || text.size() < n) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((b(k) & 0xC0) != 0x80) return 0;
  if (c == 0xE0 && b(1) < 0xA0) return 0;   // overlong
  if (c == 0xED && b(1) >= 0xA0) return 0;  // surrogates
  if (c == 0xF0 && b(1) < 0x90) return 0;   // overlong
  if (c == 0xF4 && b(1) >= 0x90) return 0;  // above U+10FFFF
  return n;
}

/// User text for a message: control characters and bytes that are not UTF-8 escaped, so the message
/// stays one line of text, cut after `limit` bytes (at a character boundary) with "...".
inline std::string printable(std::string_view text, std::size_t limit = 60) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (out.size() >= limit) return out + "...";  // whole characters only are appended: a boundary
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x80) {  // a valid UTF-8 sequence is kept whole; any other byte is escaped
      const std::size_t n = utf8_length(text.substr(i));
      if (n > 0) {
        out.append(text.data() + i, n);
        i += n - 1;
      } else {
        const char* hex = "0123456789abcdef";
        out += "\\x";
        out += hex[c >> 4];
        out += hex[c & 15];
      }
      continue;
    }
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c == '\r') out += "\\r";
    else if (c < 0x20 || c == 0x7F) {
      const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else out += static_cast<char>(c);
  }
  return out;
}

/// A value quoted in a message, compact JSON of at most `limit` characters ("..." when cut). Walked
/// with an explicit stack and stopped at the limit: never recursive, never the whole of a huge value.
template <class Json>
std::string shown(const Json& value, std::size_t limit = 60) {
  struct Frame {
    typename Json::const_iterator it, end;
    bool object, first;
  };
  std::vector<Frame> open;
  std::string out;
  auto visit = [&](const Json& v) {
    if (v.is_object() || v.is_array()) {
      out += v.is_object() ? '{' : '[';
      open.push_back({v.cbegin(), v.cend(), v.is_object(), true});
    } else if (v.is_string()) {  // only the start of a long string is dumped (invalid UTF-8 replaced)
      const auto& s = v.template get_ref<const typename Json::string_t&>();
      out += Json(s.substr(0, limit + 1)).dump(-1, ' ', false, Json::error_handler_t::replace);
    } else {
      out += v.dump();
    }
  };
  visit(value);
  while (!open.empty() && out.size() <= limit) {
    Frame& f = open.back();
    if (f.it == f.end) {
      out += f.object ? '}' : ']';
      open.pop_back();
      continue;
    }
    if (!f.first) out += ',';
    f.first = false;
    const auto it = f.it++;
    if (f.object) out += Json(it.key()).dump(-1, ' ', false, Json::error_handler_t::replace) + ':';
    visit(*it);  // may grow `open`: `f` is not used after this
  }
  if (out.size() <= limit) return out;
  out.resize(limit - 3);
  while (!out.empty() && (static_cast<unsigned char>(out.back()) & 0xC0) == 0x80) out.pop_back();
  if (!out.empty() && static_cast<unsigned char>(out.back()) >= 0xC0) out.pop_back();
  return out + "...";
}

namespace detail {

/// "line L, column C" of a byte offset; columns count characters, as editors do.
inline std::string position(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') line++, column = 1;
    else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) column++;
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

/// Offset of the first byte that is not well-formed UTF-8 (overlong forms, surrogates and code points
/// past U+10FFFF included), or npos.
inline std::size_t invalid_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    const std::size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    if (n == 0 || i + n > s.size()) return i;
    const auto c1 = static_cast<unsigned char>(s[i + 1]);
    const unsigned char lo = c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80;
    const unsigned char hi = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
    if (c1 < lo || c1 > hi) return i;
    for (std::size_t k = 2; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return i;
    i += n;
  }
  return std::string_view::npos;
}

/// A char iterator that tells how far the parser has read, so an event can be given a position.
struct TrackedIterator {
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;
  const char* at = nullptr;
  const char** read = nullptr;  ///< one past the last character the parser took
  reference operator*() const { return *at; }
  TrackedIterator& operator++() {
    *read = ++at;
    return *this;
  }
  TrackedIterator operator++(int) {
    TrackedIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const TrackedIterator& o) const { return at == o.at; }
};

/// Builds the value like nlohmann's own DOM parser, refusing too deep nesting, duplicate keys and
/// numbers that overflow; throws Error.
template <class Json>
class Builder {
 public:
  using number_integer_t = typename Json::number_integer_t;
  using number_unsigned_t = typename Json::number_unsigned_t;
  using number_float_t = typename Json::number_float_t;
  using string_t = typename Json::string_t;
  using binary_t = typename Json::binary_t;

  Builder(Json& root, std::string_view text, const std::string& where, const char* const& read)
      : root_(root), text_(text), where_(where), read_(read) {}

  bool null() { return add(Json(nullptr)); }
  bool boolean(bool v) { return add(Json(v)); }
  bool number_integer(number_integer_t v) { return add(Json(v)); }
  bool number_unsigned(number_unsigned_t v) { return add(Json(v)); }
  bool number_float(number_float_t v, const string_t&) { return add(Json(v)); }
  bool string(string_t& v) { return add(Json(std::move(v))); }
  bool binary(binary_t& v) { return add(Json(std::move(v))); }
  bool start_object(std::size_t) { return open(Json::object()); }
  bool start_array(std::size_t) { return open(Json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(string_t& k) {
    Frame& f = open_.back();
    if (!f.keys.insert(k).second)
      throw Error(where_ + ": " + path(k) + ": duplicate key at " + position(text_, key_start()) + " (each key may appear once)");
    f.key = std::move(k);
    return true;
  }

  bool parse_error(std::size_t byte, const std::string& token, const typename Json::exception& e) {
    if (e.id == 406) {  // a number too large for a double; `byte` is just past it
      const std::size_t start = byte >= token.size() ? byte - token.size() : 0;
      throw Error(where_ + ": " + position(text_, start) + ": " + printable(token) +
                  " does not fit a double (allowed: finite numbers, at most 1.7976931348623157e+308 in size)");
    }
    // `byte` counts from 1 and is the size + 1 at the end of the input.
    std::size_t at = std::min(byte > 0 ? byte - 1 : 0, text_.size());
    while (at > 0 && is_word(text_[at - 1])) --at;  // the start of a bare word such as NaN
    std::size_t end = at;
    while (end < text_.size() && is_word(text_[end])) ++end;
    std::string word(text_.substr(at, end - at));
    std::transform(word.begin(), word.end(), word.begin(), [](char c) { return static_cast<char>(std::tolower(c)); });
    if (word.starts_with('-') || word.starts_with('+')) word.erase(0, 1);
    if (word == "nan" || word == "inf" || word == "infinity")
      throw Error(where_ + ": " + position(text_, at) + ": JSON has no NaN or Infinity (allowed: finite numbers)");
    // nlohmann's description without its "[json.exception.parse_error.101] parse error at line 3, column 7: ".
    std::string what = e.what();
    if (const auto p = what.find("] "); p != std::string::npos) what.erase(0, p + 2);
    if (const auto p = what.find(": "); what.starts_with("parse error") && p != std::string::npos) what.erase(0, p + 2);
    throw Error(where_ + ": " + position(text_, std::min(byte > 0 ? byte - 1 : 0, text_.size())) + ": invalid JSON: " +
                printable(what, 200));
  }

 private:
  struct Frame {
    Json* value;
    std::unordered_set<string_t> keys;  ///< objects: the keys so far
    string_t key;                       ///< objects: the key of the value being read
  };

  static bool is_word(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '-' || c == '+'; }

  /// The path of `key` in the object being read ("tests[2].drone.mass").
  std::string path(const string_t& key) const {
    std::string out;  // appended piece by piece: GCC 12 warns (-Wrestrict) on "[" + ...
    auto join = [&](const string_t& k) {
      if (!out.empty()) out += '.';
      out += printable(k);
    };
    for (std::size_t i = 0; i + 1 < open_.size(); ++i) {  // each open container's value being read
      if (!open_[i].value->is_array()) {
        join(open_[i].key);
        continue;
      }
      out += '[';
      out += std::to_string(open_[i].value->size() - 1);
      out += ']';
    }
    join(key);
    return out;
  }
  /// Where the key just read starts: the parser has just read its closing quote.
  std::size_t key_start() const {
    std::size_t at = static_cast<std::size_t>(read_ - text_.data()) - 1;
    while (at-- > 0) {
      std::size_t slashes = 0;
      while (slashes < at && text_[at - 1 - slashes] == '\\') ++slashes;
      if (text_[at] == '"' && slashes % 2 == 0) return at;
    }
    return 0;
  }

  Json* add(Json&& v) {
    if (open_.empty()) return &(root_ = std::move(v));
    Frame& f = open_.back();
    if (f.value->is_array()) {
      f.value->push_back(std::move(v));
      return &f.value->back();
    }
    auto& object = f.value->template get_ref<typename Json::object_t&>();
    if constexpr (requires { typename Json::object_t::Container; }) {
      // ordered_json: keys are known to be new, so append without its linear search.
      auto& items = static_cast<typename Json::object_t::Container&>(object);
      return &items.emplace_back(f.key, std::move(v)).second;  // f.key stays: paths in messages use it
    } else {
      return &object.emplace(f.key, std::move(v)).first->second;
    }
  }
  bool open(Json&& container) {
    if (open_.size() >= max_depth)
      throw Error(where_ + ": " + position(text_, static_cast<std::size_t>(read_ - text_.data()) - 1) + ": nested deeper than " +
                  std::to_string(max_depth) + " levels (allowed: at most " + std::to_string(max_depth) + ")");
    open_.push_back({add(std::move(container)), {}, {}});
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }

  Json& root_;
  std::string_view text_;
  const std::string& where_;
  const char* const& read_;
  std::vector<Frame> open_;
};

}  // namespace detail

/// Parses JSON text; `where` starts every message (a file name, or "queue.json: tests[2]").
/// Throws Error.
template <class Json>
Json parse(std::string_view text, const std::string& where) {
  if (const std::size_t bad = detail::invalid_utf8(text); bad != std::string_view::npos) {
    const auto c = static_cast<unsigned char>(text[bad]);
    const char* hex = "0123456789ABCDEF";
    const bool utf16 = text.starts_with("\xFF\xFE") || text.starts_with("\xFE\xFF");
    throw Error(where + ": " + detail::position(text, bad) + ": not UTF-8 text (byte 0x" + hex[c >> 4] + hex[c & 15] +
                (utf16 ? "; the file is UTF-16" : "") + "; allowed: JSON in UTF-8)");
  }
  Json root;
  const char* read = text.data();
  detail::Builder<Json> builder(root, text, where, read);
  Json::sax_parse(detail::TrackedIterator{text.data(), &read}, detail::TrackedIterator{text.data() + text.size(), &read},
                  &builder);
  return root;
}

/// Reads and parses a file. `expected` says what the file should hold, for the message about an
/// empty one (e.g. "a test, a list of tests or {\"tests\": [...]}"). Throws Error.
template <class Json>
Json read_file(const std::filesystem::path& file, std::string_view expected) {
  const std::string name = printable(file.string(), 200);
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw Error(name + ": is a folder, not a file (expected " + std::string(expected) + ")");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(name + ": cannot open file (" + std::strerror(errno) + ")");
  // Read one byte past the limit: file sizes are not known for pipes and special files.
  std::string text;
  std::vector<char> chunk(1 << 16);
  do {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
  } while (in && text.size() <= max_file_bytes);
  if (in.bad()) throw Error(name + ": cannot read file (" + std::strerror(errno) + ")");
  if (text.size() > max_file_bytes)
    throw Error(name + ": larger than " + std::to_string(max_file_bytes >> 20) + " MiB (allowed: at most " +
                std::to_string(max_file_bytes >> 20) + " MiB; is it the file you meant?)");
  std::string_view body = text;
  if (body.starts_with("\xEF\xBB\xBF")) body.remove_prefix(3);  // a UTF-8 byte-order mark, which some editors write
  if (body.find_first_not_of(" \t\r\n") == std::string_view::npos)
    throw Error(name + ": the file is empty (expected " + std::string(expected) + ")");
  return parse<Json>(text, name);
}

}  // namespace salsa::strict_json
