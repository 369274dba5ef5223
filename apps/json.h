// The one JSON writer of the commands: string escaping, numbers, objects and arrays, for every summary
// line they print and every JSON file they write (stats.json, profile.json, bench_vsm.json, inspect).
// Members keep the order they are added in, so outputs keep their field order.
#pragma once
#include <concepts>
#include <string>
#include <string_view>
#include <vector>

namespace ml::json {

// A string literal with its quotes. '"', '\\', the C0 controls and DEL (0x7F) are escaped as \u00XX
// ('"' and '\\' as \" and \\): JSON does not require DEL escaped, but a terminal showing the line
// would act on it, and io::escapeText treats it as a control character too. Other bytes pass as they are.
std::string quote(std::string_view text);
// A number through printf's format (default "%.6g", what an ostream writes by default).
std::string number(double value, const char* format = "%.6g");
// "[a, b]": items already in JSON between `open` and `close` ("[]" when there are none): a line of its
// own per item takes separator ",\n" and open "[\n".
std::string array(const std::vector<std::string>& items, std::string_view separator = ", ",
                  std::string_view open = "[", std::string_view close = "]");

enum class Style {
    Spaced,  // {"a": 1, "b": 2}: the one-line summaries
    Compact, // {"a":1,"b":2}: trace events (profile.json)
    Lines,   // one member per line, indented by two spaces: files read by people (stats.json)
};

class Object {
  public:
    Object& text(std::string_view key, std::string_view value) { return raw(key, quote(value)); }
    template <std::integral T> Object& integer(std::string_view key, T value) {
        return raw(key, std::to_string(value));
    }
    Object& real(std::string_view key, double value, const char* format = "%.6g") {
        return raw(key, number(value, format));
    }
    // A value already in JSON: a nested object or array.
    Object& raw(std::string_view key, std::string value);
    // Another object's members after this one's.
    Object& append(const Object& other) {
        members_.insert(members_.end(), other.members_.begin(), other.members_.end());
        return *this;
    }
    // The next member starts a new line, after one space (Spaced style only: inspect's layout).
    Object& breakLine();
    bool empty() const { return members_.empty(); }
    std::string str(Style style = Style::Spaced) const;

  private:
    struct Member {
        std::string key, value;
        bool newLine = false;
    };
    std::vector<Member> members_;
    bool breakNext_ = false;
};

} // namespace ml::json
