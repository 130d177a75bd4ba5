#include "json/bounded_json.hpp"

#include <optional>
#include <utility>
#include <vector>

namespace surfdeform {
namespace {

using nlohmann::json;

Status Malformed(std::string message, std::string field) {
  return Status(ErrorCode::kMalformed, std::move(message), std::move(field));
}

// nlohmann's SAX events, building the document. Each open container is a
// frame: the container, and for an object the member its next value fills.
// Members are found by the object's own map lookup, so a duplicate key costs
// O(log n) and its path is spelled only when there is one. A member to skip
// is read past (its nested containers counted, nothing kept).
class DocumentBuilder {
 public:
  DocumentBuilder(const JsonLimits& limits, const std::string& what,
                  const JsonCheckpoint& checkpoint)
      : limits_(limits), what_(what), checkpoint_(checkpoint) {}

  bool null() { return Value(nullptr); }
  bool boolean(bool v) { return Value(v); }
  bool number_integer(json::number_integer_t v) { return Value(v); }
  bool number_unsigned(json::number_unsigned_t v) { return Value(v); }
  bool number_float(json::number_float_t v, const std::string&) { return Value(v); }
  bool string(std::string& s) {
    if (skipping_ > 0) return Skipped();
    return CountString(s.size()) && Value(std::move(s));
  }
  bool binary(json::binary_t&) { return Value(nullptr); }  // JSON text has none

  bool start_object(size_t) { return Open(json::value_t::object); }
  bool key(std::string& k) {
    if (skipping_ > 0) return true;
    Frame& f = stack_.back();
    if (limits_.skip_member && limits_.skip_member(f.parent_key, k)) {
      skipping_ = 1;  // the member's value, then back
      ++skipped_;
      return true;
    }
    if (!CountString(k.size())) return false;
    auto [it, inserted] = f.container->get_ref<json::object_t&>().emplace(std::move(k), nullptr);
    if (!inserted) {
      const std::string path = JsonPath(PathOfOpen(), it->first);
      error_ = Malformed(
          what_ + " gives the key \"" + path.substr(0, 80) + "\" twice; give each key once",
          JsonPath(what_, path));
      return false;
    }
    f.key = &it->first;
    f.member = &it->second;
    return true;
  }
  bool end_object() { return Close(); }
  bool start_array(size_t) { return Open(json::value_t::array); }
  bool end_array() { return Close(); }

  bool parse_error(size_t position, const std::string&, const nlohmann::detail::exception& e) {
    if (e.id == 406) {  // a number past the range of doubles
      error_ = InvalidArgument(
          what_ + " holds a number beyond the range of doubles (JSON has no infinity)", what_);
    } else {
      error_ = Malformed(
          what_ + " is not valid JSON (syntax error at byte " + std::to_string(position) + ")",
          what_);
    }
    return false;
  }

  Result<json> Take(bool parsed) {
    if (error_) return *error_;
    if (!parsed) return Malformed(what_ + " is not valid JSON", what_);
    return std::move(root_);
  }
  size_t skipped() const { return skipped_; }

 private:
  struct Frame {
    json* container;
    std::string_view parent_key;       // the key this container is the value of
    const std::string* key = nullptr;  // an object's member being filled
    json* member = nullptr;
  };

  // A value inside a skipped member: the member ends with the value that
  // brings the skip depth back to zero.
  bool Skipped() {
    if (skipping_ == 1) skipping_ = 0;
    return true;
  }

  bool Count() {
    if (++elements_ > limits_.max_elements) {
      error_ = Status::LimitExceeded(
          what_ + " has more than " + std::to_string(limits_.max_elements) +
              " JSON values (numbers, strings, arrays, objects); send large point sets as a "
              "mesh file",
          JsonPath(what_, PathOfOpen()), static_cast<double>(limits_.max_elements),
          static_cast<double>(elements_));
      return false;
    }
    // Every few microseconds of parsing: a spent budget or a cancelled
    // request stops the parse at once, and the clock is read rarely enough
    // not to show in the parse's time.
    if (elements_ % kJsonCheckpointValues == 0 && checkpoint_) {
      Status s = checkpoint_();
      if (!s.ok()) {
        error_ = std::move(s);
        return false;
      }
    }
    return true;
  }

  bool CountString(size_t bytes) {
    string_bytes_ += bytes;
    if (string_bytes_ <= limits_.max_string_bytes) return true;
    error_ = Status::LimitExceeded(
        what_ + " has more than " + std::to_string(limits_.max_string_bytes) +
            " bytes of keys and strings",
        JsonPath(what_, PathOfOpen()), static_cast<double>(limits_.max_string_bytes),
        static_cast<double>(string_bytes_));
    return false;
  }

  template <typename V>
  json* Place(V&& v) {
    if (stack_.empty()) {
      root_ = json(std::forward<V>(v));
      return &root_;
    }
    Frame& f = stack_.back();
    if (f.container->is_array()) {
      auto& array = f.container->get_ref<json::array_t&>();
      array.emplace_back(std::forward<V>(v));
      return &array.back();
    }
    *f.member = json(std::forward<V>(v));
    return f.member;
  }

  template <typename V>
  bool Value(V&& v) {
    if (skipping_ > 0) return Skipped();
    if (!Count()) return false;
    Place(std::forward<V>(v));
    return true;
  }

  bool Open(json::value_t type) {
    const size_t depth = stack_.size() + (skipping_ > 0 ? skipping_ - 1 : 0);
    if (depth >= static_cast<size_t>(limits_.max_depth)) {
      // Malformed (400) rather than too large: no sensible document nests this deep.
      error_ = Malformed(what_ + " nests more than " + std::to_string(limits_.max_depth) +
                             " levels deep; the limit is " + std::to_string(limits_.max_depth),
                         what_)
                   .WithLimit(limits_.max_depth, static_cast<double>(depth + 1));
      return false;
    }
    if (skipping_ > 0) {
      ++skipping_;
      return true;
    }
    if (!Count()) return false;
    std::string_view parent_key;
    if (!stack_.empty() && stack_.back().key != nullptr && !stack_.back().container->is_array()) {
      parent_key = *stack_.back().key;
    }
    stack_.push_back(Frame{Place(json(type)), parent_key});
    return true;
  }

  bool Close() {
    if (skipping_ > 0) {
      --skipping_;
      return skipping_ == 1 ? Skipped() : true;
    }
    stack_.pop_back();
    return true;
  }

  // "a.b[3]": the path of the innermost open container, for messages.
  std::string PathOfOpen() const {
    std::string path;
    for (size_t k = 0; k + 1 < stack_.size(); ++k) {
      const Frame& f = stack_[k];
      if (f.container->is_array()) {
        path = JsonPath(path, f.container->size() - 1);
      } else if (f.key != nullptr) {
        path = JsonPath(path, *f.key);
      }
    }
    return path;
  }

  const JsonLimits& limits_;
  const std::string& what_;
  const JsonCheckpoint& checkpoint_;
  json root_;
  std::vector<Frame> stack_;
  size_t elements_ = 0;
  size_t string_bytes_ = 0;
  // Inside a skipped member: 1 waiting for its value, 1 + n inside n of its
  // open containers.
  size_t skipping_ = 0;
  size_t skipped_ = 0;
  std::optional<Status> error_;
};

}  // namespace

std::string JsonPath(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

std::string JsonPath(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

Result<json> ParseBoundedJson(std::string_view text, const JsonLimits& limits,
                              const std::string& what, const JsonCheckpoint& checkpoint,
                              size_t* skipped) {
  DocumentBuilder builder(limits, what, checkpoint);
  bool parsed = false;
  try {
    parsed = json::sax_parse(text.begin(), text.end(), &builder);
  } catch (const json::exception&) {
    parsed = false;
  }
  if (skipped != nullptr) *skipped = builder.skipped();
  return builder.Take(parsed);
}

}  // namespace surfdeform
