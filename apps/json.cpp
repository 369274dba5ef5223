#include "apps/json.h"

#include <cstdio>

namespace ml::json {

std::string quote(std::string_view text) {
    std::string o = "\"";
    for (unsigned char c : text) {
        if (c == '"' || c == '\\') {
            o += '\\', o += char(c);
        } else if (c < 0x20 || c == 0x7F) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            o += buf;
        } else {
            o += char(c);
        }
    }
    return o + "\"";
}

std::string number(double value, const char* format) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, value);
    return buf;
}

std::string array(const std::vector<std::string>& items, std::string_view separator, std::string_view open,
                  std::string_view close) {
    if (items.empty()) return "[]";
    std::string o(open);
    for (size_t i = 0; i < items.size(); ++i) {
        if (i) o += separator;
        o += items[i];
    }
    return o += close;
}

Object& Object::raw(std::string_view key, std::string value) {
    members_.push_back({std::string(key), std::move(value), breakNext_});
    breakNext_ = false;
    return *this;
}

Object& Object::breakLine() {
    breakNext_ = true;
    return *this;
}

std::string Object::str(Style style) const {
    const bool lines = style == Style::Lines, compact = style == Style::Compact;
    std::string o = lines ? "{\n  " : "{";
    for (size_t i = 0; i < members_.size(); ++i) {
        const Member& m = members_[i];
        if (i) o += lines ? ",\n  " : compact ? "," : m.newLine ? ",\n " : ", ";
        o += quote(m.key);
        o += compact ? ":" : ": ";
        o += m.value;
    }
    return o + (lines ? "\n}" : "}");
}

} // namespace ml::json
