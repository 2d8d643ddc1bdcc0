#include "scene/json_text.h"

#include "base/error.h"

#include <cmath>
#include <set>
#include <vector>

namespace veil::scene {

using nlohmann::json;

std::optional<std::size_t> excessiveNestingAt(std::string_view text) {
    std::size_t depth = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '"') {
            for (++i; i < text.size() && text[i] != '"'; ++i)
                if (text[i] == '\\') ++i;
        } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
            while (i < text.size() && text[i] != '\n')
                ++i;
        } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
            const std::size_t end = text.find("*/", i + 2);
            if (end == std::string_view::npos) return std::nullopt; // the parser reports it
            i = end + 1;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth) return i;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return std::nullopt;
}

std::string lineColumn(std::string_view text, std::size_t offset) {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return fmt::format("line {}, column {}", line, column);
}

std::string jsonProblem(const json::exception& e) {
    std::string s = e.what();
    if (s.rfind("[json.exception.", 0) == 0) {
        const std::size_t close = s.find("] ");
        if (close != std::string::npos) s.erase(0, close + 2);
    }
    return s;
}

namespace {

// Where the parser is: one entry per open array or object.
struct Frame {
    bool array = false;
    std::size_t index = 0;      // arrays: elements completed so far
    std::string key;            // objects: the last key read
    std::set<std::string> keys; // objects: all keys read, to refuse duplicates
};

std::string pointer(const std::vector<Frame>& stack) {
    std::string out;
    for (const Frame& f : stack) {
        if (f.array) {
            out += fmt::format("/{}", f.index);
        } else if (!f.keys.empty()) { // "" is a key too: {"": 1} has "/" as its pointer
            out += '/';
            for (char c : f.key) { // RFC 6901
                if (c == '~')
                    out += "~0";
                else if (c == '/')
                    out += "~1";
                else
                    out += c;
            }
        }
    }
    return out;
}

void describe(const json& v, std::string& out, std::size_t budget) {
    if (out.size() > budget) return;
    const auto scalar = [](const json& s) {
        return s.dump(-1, ' ', false, json::error_handler_t::replace);
    };
    switch (v.type()) {
    case json::value_t::object: {
        out += '{';
        bool first = true;
        for (auto it = v.begin(); it != v.end() && out.size() <= budget; ++it) {
            if (!first) out += ',';
            out += scalar(json(it.key().substr(0, budget)));
            out += ':';
            first = false;
            describe(it.value(), out, budget);
        }
        out += '}';
        break;
    }
    case json::value_t::array: {
        out += '[';
        bool first = true;
        for (auto it = v.begin(); it != v.end() && out.size() <= budget; ++it) {
            if (!first) out += ',';
            first = false;
            describe(*it, out, budget);
        }
        out += ']';
        break;
    }
    case json::value_t::string:
        out += scalar(json(v.get_ref<const std::string&>().substr(0, budget + 1)));
        break;
    case json::value_t::number_float:
        if (!std::isfinite(v.get<double>())) {
            out += fmt::format("{}", v.get<double>());
            break;
        }
        [[fallthrough]];
    default:
        out += scalar(v);
    }
}

} // namespace

std::string describeJson(const json& v, std::size_t maxChars) {
    std::string out;
    describe(v, out, maxChars);
    if (out.size() > maxChars) out = out.substr(0, maxChars > 3 ? maxChars - 3 : 0) + "...";
    return out;
}

json parseJsonText(std::string_view text, const std::string& source) {
    if (const auto at = excessiveNestingAt(text))
        throw Error(fmt::format("{}: invalid JSON: nested deeper than {} levels at {}", source,
                                kMaxJsonDepth, lineColumn(text, *at)));
    std::vector<Frame> stack;
    const json::parser_callback_t track = [&](int, json::parse_event_t event, json& parsed) {
        switch (event) {
        case json::parse_event_t::object_start:
            stack.push_back({false, 0, {}, {}});
            break;
        case json::parse_event_t::array_start:
            stack.push_back({true, 0, {}, {}});
            break;
        case json::parse_event_t::key:
            stack.back().key = parsed.get<std::string>();
            // nlohmann keeps the last of duplicate keys: the first would be silently lost.
            if (!stack.back().keys.insert(stack.back().key).second)
                throw Error(fmt::format("{}: {}: duplicate key '{}'", source, pointer(stack),
                                        stack.back().key));
            break;
        case json::parse_event_t::object_end:
        case json::parse_event_t::array_end:
            stack.pop_back();
            if (!stack.empty() && stack.back().array) ++stack.back().index;
            break;
        case json::parse_event_t::value:
            if (!stack.empty() && stack.back().array) ++stack.back().index;
            break;
        }
        return true;
    };
    try {
        return json::parse(text.begin(), text.end(), track, true, true);
    } catch (const json::exception& e) {
        const std::string where = pointer(stack);
        throw Error(fmt::format("{}: {}invalid JSON: {}", source, where.empty() ? "" : where + ": ",
                                jsonProblem(e)));
    }
}

} // namespace veil::scene
