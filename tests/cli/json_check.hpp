// A strict JSON reader for the CLI tests: checks what --stats json prints and reads it back.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fdmsurf_cli_test {

struct JsonValue {
    enum class Type { Null, Bool, Number, String, Array, Object };
    Type type = Type::Null;
    bool boolean = false;
    double number = 0.0;
    std::string string;  // decoded UTF-8
    std::vector<JsonValue> array;
    std::vector<JsonValue> object;  // members in order, each with its key; duplicates kept
    std::string key;                // the name of a member of an object

    // The first member of an object named `name`, or null.
    const JsonValue* find(std::string_view name) const;
};

inline const JsonValue* JsonValue::find(std::string_view name) const {
    for (const JsonValue& member : object) {
        if (member.key == name) return &member;
    }
    return nullptr;
}

// RFC 8259 grammar; nullopt for anything else, including text after the value.
class JsonParser {
public:
    explicit JsonParser(std::string_view text) : text_(text) {}

    std::optional<JsonValue> parse() {
        JsonValue value;
        skip_space();
        if (!parse_value(value, 0)) return std::nullopt;
        skip_space();
        if (pos_ != text_.size()) return std::nullopt;
        return value;
    }

private:
    bool parse_value(JsonValue& v, int depth) {
        if (depth > 64 || pos_ >= text_.size()) return false;
        const char c = text_[pos_];
        if (c == '{') return parse_object(v, depth);
        if (c == '[') return parse_array(v, depth);
        if (c == '"') {
            v.type = JsonValue::Type::String;
            return parse_string(v.string);
        }
        if (literal("true")) {
            v.type = JsonValue::Type::Bool;
            v.boolean = true;
            return true;
        }
        if (literal("false")) {
            v.type = JsonValue::Type::Bool;
            return true;
        }
        if (literal("null")) return true;
        return parse_number(v);
    }

    bool parse_object(JsonValue& v, int depth) {
        v.type = JsonValue::Type::Object;
        ++pos_;
        skip_space();
        if (eat('}')) return true;
        while (true) {
            std::string key;
            skip_space();
            if (pos_ >= text_.size() || text_[pos_] != '"' || !parse_string(key)) return false;
            skip_space();
            if (!eat(':')) return false;
            skip_space();
            JsonValue member;
            if (!parse_value(member, depth + 1)) return false;
            member.key = std::move(key);
            v.object.push_back(std::move(member));
            skip_space();
            if (eat('}')) return true;
            if (!eat(',')) return false;
        }
    }

    bool parse_array(JsonValue& v, int depth) {
        v.type = JsonValue::Type::Array;
        ++pos_;
        skip_space();
        if (eat(']')) return true;
        while (true) {
            skip_space();
            JsonValue element;
            if (!parse_value(element, depth + 1)) return false;
            v.array.push_back(std::move(element));
            skip_space();
            if (eat(']')) return true;
            if (!eat(',')) return false;
        }
    }

    bool parse_string(std::string& out) {
        ++pos_;  // the opening quote
        while (pos_ < text_.size()) {
            const auto c = static_cast<unsigned char>(text_[pos_++]);
            if (c == '"') return true;
            if (c < 0x20) return false;
            if (c != '\\') {
                out += static_cast<char>(c);
                continue;
            }
            if (pos_ >= text_.size()) return false;
            const char e = text_[pos_++];
            switch (e) {
                case '"':
                    out += '"';
                    break;
                case '\\':
                    out += '\\';
                    break;
                case '/':
                    out += '/';
                    break;
                case 'b':
                    out += '\b';
                    break;
                case 'f':
                    out += '\f';
                    break;
                case 'n':
                    out += '\n';
                    break;
                case 'r':
                    out += '\r';
                    break;
                case 't':
                    out += '\t';
                    break;
                case 'u': {
                    std::uint32_t code = 0;
                    if (!hex4(code)) return false;
                    if (code >= 0xd800 && code <= 0xdbff) {
                        std::uint32_t low = 0;
                        if (!eat('\\') || !eat('u') || !hex4(low) || low < 0xdc00 || low > 0xdfff) {
                            return false;
                        }
                        code = 0x10000 + ((code - 0xd800) << 10) + (low - 0xdc00);
                    } else if (code >= 0xdc00 && code <= 0xdfff) {
                        return false;
                    }
                    append_utf8(out, code);
                    break;
                }
                default:
                    return false;
            }
        }
        return false;
    }

    bool parse_number(JsonValue& v) {
        const std::size_t start = pos_;
        eat('-');
        if (!eat('0') && !digits()) return false;
        if (eat('.') && !digits()) return false;
        if (eat('e') || eat('E')) {
            if (!eat('+')) eat('-');
            if (!digits()) return false;
        }
        v.type = JsonValue::Type::Number;
        v.number = std::strtod(std::string(text_.substr(start, pos_ - start)).c_str(), nullptr);
        return true;
    }

    bool digits() {
        const std::size_t start = pos_;
        while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
        return pos_ != start;
    }

    bool hex4(std::uint32_t& code) {
        for (int i = 0; i < 4; ++i) {
            if (pos_ >= text_.size()) return false;
            const char h = text_[pos_++];
            code <<= 4;
            if (h >= '0' && h <= '9')
                code |= static_cast<std::uint32_t>(h - '0');
            else if (h >= 'a' && h <= 'f')
                code |= static_cast<std::uint32_t>(h - 'a' + 10);
            else if (h >= 'A' && h <= 'F')
                code |= static_cast<std::uint32_t>(h - 'A' + 10);
            else
                return false;
        }
        return true;
    }

    static void append_utf8(std::string& out, std::uint32_t code) {
        if (code < 0x80) {
            out += static_cast<char>(code);
        } else if (code < 0x800) {
            out += static_cast<char>(0xc0 | (code >> 6));
            out += static_cast<char>(0x80 | (code & 0x3f));
        } else if (code < 0x10000) {
            out += static_cast<char>(0xe0 | (code >> 12));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
            out += static_cast<char>(0x80 | (code & 0x3f));
        } else {
            out += static_cast<char>(0xf0 | (code >> 18));
            out += static_cast<char>(0x80 | ((code >> 12) & 0x3f));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
            out += static_cast<char>(0x80 | (code & 0x3f));
        }
    }

    bool literal(std::string_view word) {
        if (text_.substr(pos_, word.size()) != word) return false;
        pos_ += word.size();
        return true;
    }

    bool eat(char c) {
        if (pos_ < text_.size() && text_[pos_] == c) {
            ++pos_;
            return true;
        }
        return false;
    }

    void skip_space() {
        while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                       text_[pos_] == '\n' || text_[pos_] == '\r')) {
            ++pos_;
        }
    }

    std::string_view text_;
    std::size_t pos_ = 0;
};

inline std::optional<JsonValue> parse_json(std::string_view text) {
    return JsonParser(text).parse();
}

}  // namespace fdmsurf_cli_test
