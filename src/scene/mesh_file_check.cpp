// The PLY pre-check of mesh_file_check.h. The format ([Turk94], "The PLY polygon file
// format"): a text header of `element <name> <count>` lines, each followed by its
// `property <type> <name>` or `property list <count type> <item type> <name>` lines, then
// `end_header` and the body, either whitespace-separated ASCII numbers or packed binary values.
#include "scene/mesh_file_check.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace veil::scene {

namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct Property {
    std::string name;
    bool list = false;
    Type countType = Type::UInt8;
    Type type = Type::Float32;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

bool parseType(const std::string& s, Type& t) {
    static const std::pair<const char*, Type> names[] = {
        {"char", Type::Int8},      {"int8", Type::Int8},       {"uchar", Type::UInt8},
        {"uint8", Type::UInt8},    {"short", Type::Int16},     {"int16", Type::Int16},
        {"ushort", Type::UInt16},  {"uint16", Type::UInt16},   {"int", Type::Int32},
        {"int32", Type::Int32},    {"uint", Type::UInt32},     {"uint32", Type::UInt32},
        {"float", Type::Float32},  {"float32", Type::Float32}, {"double", Type::Float64},
        {"float64", Type::Float64}};
    for (const auto& [name, type] : names)
        if (s == name) {
            t = type;
            return true;
        }
    return false;
}

std::size_t sizeOf(Type t) {
    switch (t) {
    case Type::Int8:
    case Type::UInt8:
        return 1;
    case Type::Int16:
    case Type::UInt16:
        return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32:
        return 4;
    case Type::Float64:
        return 8;
    }
    return 1;
}

bool isFloat(Type t) { return t == Type::Float32 || t == Type::Float64; }

// Sequential reader with a fixed buffer, so that checking a large file does not hold a copy.
class Reader {
public:
    explicit Reader(const std::filesystem::path& path) : in_(path, std::ios::binary) {}
    bool ok() const { return bool(in_); }
    // Bytes consumed so far (get, read and line).
    std::uint64_t offset() const { return base_ + pos_; }
    bool atEnd() { return !fill(); }

    int get() {
        if (!fill()) return -1;
        return static_cast<unsigned char>(buffer_[pos_++]);
    }
    bool read(unsigned char* dst, std::size_t n) {
        while (n > 0) {
            if (!fill()) return false;
            const std::size_t k = std::min(n, end_ - pos_);
            std::memcpy(dst, buffer_.data() + pos_, k);
            pos_ += k;
            dst += k;
            n -= k;
        }
        return true;
    }
    // One header line without its line ending; false at the end of the file.
    bool line(std::string& out, std::size_t limit = 4096) {
        out.clear();
        int c = get();
        if (c < 0) return false;
        while (c >= 0 && c != '\n' && out.size() < limit) {
            out.push_back(char(c));
            c = get();
        }
        if (!out.empty() && out.back() == '\r') out.pop_back();
        return true;
    }

private:
    bool fill() {
        if (pos_ < end_) return true;
        if (!in_) return false;
        base_ += end_;
        in_.read(buffer_.data(), std::streamsize(buffer_.size()));
        end_ = static_cast<std::size_t>(in_.gcount());
        pos_ = 0;
        return end_ > 0;
    }

    std::ifstream in_;
    std::vector<char> buffer_ = std::vector<char>(std::size_t(1) << 20);
    std::size_t pos_ = 0, end_ = 0;
    std::uint64_t base_ = 0;
};

std::vector<std::string> words(const std::string& line) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
            ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t')
            ++j;
        if (j > i) out.push_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

class BodyChecker {
public:
    BodyChecker(Reader& reader, Format format, std::string file, std::uint64_t headerLines)
        : reader_(reader), format_(format), file_(std::move(file)), lineNumber_(headerLines) {}

    // ASCII: the next non-empty line holds instance `index` of `e`; false at the end of the
    // file. assimp reads one instance per line, so the pre-check does too: a line with values
    // left over or missing is what assimp would read differently from the header (a face
    // list then ran into the next line's values and TriangulateProcess aborted).
    bool beginInstance() {
        if (format_ != Format::Ascii) return true;
        std::string text;
        do {
            if (!reader_.line(text, kMaxLine + 1)) return false;
            ++lineNumber_;
            VEIL_CHECK(text.size() <= kMaxLine, "mesh file '{}': line {} is over {} characters",
                       file_, lineNumber_, kMaxLine);
            tokens_ = words(text);
        } while (tokens_.empty());
        next_ = 0;
        return true;
    }
    void endInstance(const Element& e, std::uint64_t index) const {
        VEIL_CHECK(format_ != Format::Ascii || next_ == tokens_.size(),
                   "mesh file '{}': line {} ({} {}) has {} values, but the header's properties "
                   "of '{}' give {}",
                   file_, lineNumber_, e.name, index, tokens_.size(), e.name, next_);
    }

    // One value of type `t`; false at the end of the file. Throws on a malformed ASCII value.
    bool value(Type t, double& out, const Element& e, std::uint64_t index) {
        if (format_ == Format::Ascii) {
            if (next_ == tokens_.size() && reader_.atEnd()) return false; // the file is cut
            VEIL_CHECK(next_ < tokens_.size(),
                       "mesh file '{}': line {} ({} {}) has {} values, fewer than the header's "
                       "properties of '{}' give",
                       file_, lineNumber_, e.name, index, tokens_.size(), e.name);
            token_ = tokens_[next_++];
            char* end = nullptr;
            out = std::strtod(token_.c_str(), &end);
            VEIL_CHECK(end != token_.c_str() && *end == '\0' &&
                           (isFloat(t) || out == std::floor(out)),
                       "mesh file '{}': element '{}' {} holds '{}', not a {} value", file_, e.name,
                       index, token_, isFloat(t) ? "numeric" : "integer");
            return true;
        }
        unsigned char b[8];
        const std::size_t n = sizeOf(t);
        if (!reader_.read(b, n)) return false;
        if (format_ == Format::BinaryBig) std::reverse(b, b + n);
        switch (t) {
        case Type::Int8:
            out = static_cast<std::int8_t>(b[0]);
            break;
        case Type::UInt8:
            out = b[0];
            break;
        case Type::Int16:
            out = load<std::int16_t>(b);
            break;
        case Type::UInt16:
            out = load<std::uint16_t>(b);
            break;
        case Type::Int32:
            out = load<std::int32_t>(b);
            break;
        case Type::UInt32:
            out = load<std::uint32_t>(b);
            break;
        case Type::Float32:
            out = load<float>(b);
            break;
        case Type::Float64:
            out = load<double>(b);
            break;
        }
        return true;
    }

    void element(const Element& e, std::uint64_t vertexCount) {
        if (e.properties.empty()) return;
        // Strips use -1 as the restart marker; faces index vertices only.
        const bool faces = e.name == "face" || e.name == "tristrips";
        const double lowest = e.name == "tristrips" ? -1.0 : 0.0;
        for (std::uint64_t i = 0; i < e.count; ++i) {
            if (!beginInstance()) truncated(e, i);
            for (const Property& p : e.properties) {
                double v = 0.0;
                if (!p.list) {
                    if (!value(p.type, v, e, i)) truncated(e, i);
                    continue;
                }
                double n = 0.0;
                if (!value(p.countType, n, e, i)) truncated(e, i);
                VEIL_CHECK(n >= 0.0 && !isFloat(p.countType),
                           "mesh file '{}': element '{}' {} has a list of {} entries", file_,
                           e.name, i, n);
                const bool indices =
                    faces && (p.name == "vertex_indices" || p.name == "vertex_index");
                // assimp's TriangulateProcess aborts (ai_assert) on a face without indices.
                VEIL_CHECK(!indices || n > 0 || e.name != "face",
                           "mesh file '{}': face {} has no vertex indices", file_, i);
                for (double k = 0; k < n; ++k) {
                    if (!value(p.type, v, e, i)) truncated(e, i);
                    VEIL_CHECK(!indices || v == lowest ||
                                   (v >= 0.0 && v < double(vertexCount) && v == std::floor(v)),
                               "mesh file '{}': {} {} refers to vertex {}, but the file has {} "
                               "vertices",
                               file_, e.name, i, v, vertexCount);
                }
            }
            endInstance(e, i);
        }
    }

private:
    template <typename T>
    static T load(const unsigned char* b) {
        T v;
        std::memcpy(&v, b, sizeof(T));
        return v;
    }
    [[noreturn]] void truncated(const Element& e, std::uint64_t i) const {
        throw Error(fmt::format("mesh file '{}' is truncated: it ends inside element '{}' {} of {}",
                                file_, e.name, i, e.count));
    }

    static constexpr std::size_t kMaxLine = std::size_t(1) << 20;

    Reader& reader_;
    Format format_;
    std::string file_;
    std::string token_;
    std::uint64_t lineNumber_;        // ASCII: the line of the current instance
    std::vector<std::string> tokens_; // ASCII: its values
    std::size_t next_ = 0;            // ASCII: the next one to read
};

// A keyword for an error message: printable, at most 40 characters.
std::string boundedKeyword(const std::string& word) {
    std::string out;
    for (char c : word.substr(0, 40)) {
        const auto u = static_cast<unsigned char>(c);
        out.push_back(u < 0x20 || u >= 0x7f ? '?' : c);
    }
    return word.size() > 40 ? out + "..." : out;
}

// A binary body's size where the layout fixes it: every element without list properties
// takes count x (sum of its property sizes) bytes, and a list takes at least its count's
// size per instance. Refuses, before the body is walked, a file too short for that minimum
// (a huge element count in a small file), with the sizes in the message.
void checkBinarySize(const std::filesystem::path& path, const std::string& file,
                     const std::vector<Element>& elements, std::uint64_t headerBytes) {
    std::error_code ec;
    const std::uint64_t fileSize = std::filesystem::file_size(path, ec);
    if (ec) return; // the walk reports what cannot be read
    const std::uint64_t body = fileSize >= headerBytes ? fileSize - headerBytes : 0;
    // Fits in a long double without overflow for any 64-bit count.
    long double minimum = 0.0L;
    bool fixed = true;
    for (const Element& e : elements) {
        std::uint64_t perInstance = 0;
        for (const Property& p : e.properties) {
            perInstance += sizeOf(p.list ? p.countType : p.type);
            fixed = fixed && !p.list;
        }
        minimum += static_cast<long double>(e.count) * static_cast<long double>(perInstance);
    }
    VEIL_CHECK(minimum <= static_cast<long double>(body),
               "mesh file '{}' is truncated: its PLY header describes a binary body of {}{:.0f} "
               "bytes, but the file has {} bytes after the header",
               file, fixed ? "" : "at least ", double(minimum), body);
    VEIL_CHECK(!fixed || minimum == static_cast<long double>(body),
               "mesh file '{}': its PLY header describes a binary body of {:.0f} bytes, but the "
               "file has {} bytes after the header (the header does not describe the body)",
               file, double(minimum), body);
}

} // namespace

void checkPlyFile(const std::filesystem::path& path) {
    const std::string file = path.string();
    Reader reader(path);
    VEIL_CHECK(reader.ok(), "cannot open mesh file '{}'", file);
    std::string line;
    VEIL_CHECK(reader.line(line) && line == "ply",
               "mesh file '{}' is not a PLY file (no 'ply' "
               "magic line)",
               file);
    bool haveFormat = false, ended = false;
    Format format = Format::Ascii;
    std::vector<Element> elements;
    std::uint64_t lineNumber = 1;
    while (reader.line(line)) {
        ++lineNumber;
        const std::vector<std::string> w = words(line);
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "end_header") {
            ended = true;
            break;
        }
        if (w[0] == "format") {
            VEIL_CHECK(w.size() >= 2 && (w[1] == "ascii" || w[1] == "binary_little_endian" ||
                                         w[1] == "binary_big_endian"),
                       "mesh file '{}': unknown PLY format line '{}'", file, line);
            format = w[1] == "ascii"                  ? Format::Ascii
                     : w[1] == "binary_little_endian" ? Format::BinaryLittle
                                                      : Format::BinaryBig;
            haveFormat = true;
        } else if (w[0] == "element") {
            char* end = nullptr;
            const unsigned long long count =
                w.size() == 3 ? std::strtoull(w[2].c_str(), &end, 10) : 0;
            VEIL_CHECK(w.size() == 3 && end && *end == '\0' && w[2][0] != '-',
                       "mesh file '{}': malformed PLY header line '{}'", file, line);
            elements.push_back({w[1], count, {}});
        } else if (w[0] == "property") {
            VEIL_CHECK(!elements.empty(), "mesh file '{}': PLY property before any element: '{}'",
                       file, line);
            Property p;
            bool ok = false;
            if (w.size() == 5 && w[1] == "list") {
                p.list = true;
                p.name = w[4];
                ok = parseType(w[2], p.countType) && parseType(w[3], p.type);
            } else if (w.size() == 3) {
                p.name = w[2];
                ok = parseType(w[1], p.type);
            }
            VEIL_CHECK(ok, "mesh file '{}': malformed PLY property line '{}'", file, line);
            elements.back().properties.push_back(p);
        } else {
            // assimp skips a line it does not know, so a misspelt `property` silently drops a
            // property and shifts every later value: a binary file is then read at the wrong
            // offsets and TriangulateProcess aborts on what it finds
            // (tests/fuzz/regressions/mesh/ply-misspelt-property-triangulate-abort). The
            // format has no vendor keywords besides comment and obj_info, so anything else
            // is an error.
            throw Error(fmt::format("mesh file '{}': line {} of the PLY header has the unknown "
                                    "keyword '{}' (expected element, property, comment, "
                                    "obj_info, format or end_header)",
                                    file, lineNumber, boundedKeyword(w[0])));
        }
    }
    VEIL_CHECK(haveFormat && ended, "mesh file '{}': PLY header without {}", file,
               haveFormat ? "'end_header'" : "a 'format' line");
    std::uint64_t vertices = 0;
    for (const Element& e : elements)
        if (e.name == "vertex") vertices = e.count;
    if (format != Format::Ascii) checkBinarySize(path, file, elements, reader.offset());
    BodyChecker body(reader, format, file, lineNumber);
    for (const Element& e : elements)
        body.element(e, vertices);
    // A binary body must end where its layout says: extra bytes mean that the header does
    // not describe the body (a property missing or of the wrong type shifts everything).
    if (format != Format::Ascii) {
        std::uint64_t extra = 0;
        while (reader.get() >= 0)
            ++extra;
        VEIL_CHECK(extra == 0,
                   "mesh file '{}': {} bytes follow the last element of the binary PLY body (the "
                   "header does not describe the body)",
                   file, extra);
    }
}

} // namespace veil::scene
