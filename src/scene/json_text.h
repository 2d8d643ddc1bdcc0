// Reading JSON text from users (scene files, --set values) without trusting it: the nesting
// depth is bounded before nlohmann's recursive code sees it, every nlohmann exception becomes
// a veil::Error naming the source and the JSON pointer, and values in messages are bounded.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace veil::scene {

// Deeper documents are refused: dump(), copies and comparisons in nlohmann recurse once per
// level, so a 500k-deep "[[[[...]]]]" overflows the stack. Scenes need fewer than 10 levels.
constexpr std::size_t kMaxJsonDepth = 256;

// Byte offset of the bracket that opens level kMaxJsonDepth + 1, or nullopt. Brackets inside
// strings and // or /* */ comments do not count.
std::optional<std::size_t> excessiveNestingAt(std::string_view text);

// "line L, column C" of a byte offset (both from 1), for messages.
std::string lineColumn(std::string_view text, std::size_t offset);

// Parses `text` (comments allowed; a key given twice in one object is an error). Errors
// throw veil::Error
// "<source>: <json pointer>: invalid JSON: <problem>", the pointer being where the parser
// stopped, e.g. "/render/width" for "width": 1e400.
nlohmann::json parseJsonText(std::string_view text, const std::string& source);

// A short one-line rendering of `v` for messages: at most maxChars characters ("..." when
// cut), never recursing deeper than that, invalid UTF-8 replaced. Never throws for depth.
std::string describeJson(const nlohmann::json& v, std::size_t maxChars = 60);

// nlohmann's message without its "[json.exception.type.id] " prefix.
std::string jsonProblem(const nlohmann::json::exception& e);

} // namespace veil::scene
