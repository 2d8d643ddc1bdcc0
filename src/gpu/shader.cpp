#include "gpu/shader.h"

#include "base/error.h"
#include "base/log.h"

#include <glm/gtc/type_ptr.hpp>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#ifndef VEIL_DEFAULT_SHADER_DIR
#define VEIL_DEFAULT_SHADER_DIR "shaders"
#endif

namespace veil::gpu {

namespace fs = std::filesystem;

namespace {

// The shaders of an installed program: <prefix>/share/veil/shaders beside <prefix>/bin/veil
// (`cmake --install`), when the running executable is one of Veil's (veil, veil-bench, ...)
// and that folder exists; empty otherwise. A program in the build tree has no such folder
// beside it; another executable (python3 running the module) is not asked, so that an
// installed tree does not replace the shaders of the build the module came from.
fs::path installedShaderDirectory() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec || exe.filename().string().rfind("veil", 0) != 0) return {};
    fs::path dir = exe.parent_path().parent_path() / "share" / "veil" / "shaders";
    return fs::is_directory(dir, ec) ? dir : fs::path();
}

} // namespace

// $VEIL_SHADER_DIR if set; else the installed tree's share/veil/shaders beside the program;
// else the source tree's shaders/ the build was configured from.
fs::path shaderDirectory() {
    if (const char* env = std::getenv("VEIL_SHADER_DIR"); env && *env) return env;
    static const fs::path installed = installedShaderDirectory();
    if (!installed.empty()) return installed;
    return VEIL_DEFAULT_SHADER_DIR;
}

namespace {

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    VEIL_CHECK(in, "cannot open shader file '{}'", path.string());
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct Preprocessor {
    fs::path root;
    std::vector<std::string> files;
    std::set<fs::path> included;
    std::vector<fs::path> stack;
    std::ostringstream out;
    std::vector<std::string> defines;
    IncludeAliases aliases;
    bool versionSeen = false;

    int fileIndex(const fs::path& p) {
        files.push_back(p.string());
        return static_cast<int>(files.size() - 1);
    }

    fs::path resolve(const std::string& name, const fs::path& from) {
        for (const auto& [alias, target] : aliases)
            if (alias == name) return resolve(target.string(), root / "x");
        fs::path local = from.parent_path() / name;
        if (fs::exists(local)) return fs::weakly_canonical(local);
        fs::path rooted = root / name;
        if (fs::exists(rooted)) return fs::weakly_canonical(rooted);
        throw Error(fmt::format("{}: #include \"{}\" not found (looked in '{}' and '{}')",
                                from.string(), name, from.parent_path().string(), root.string()));
    }

    void process(const fs::path& path) {
        for (const auto& p : stack)
            VEIL_CHECK(p != path, "{}: #include cycle", path.string());
        if (!included.insert(path).second) return; // each file once (pragma-once semantics)
        stack.push_back(path);
        const int index = fileIndex(path);
        const std::string text = readText(path);
        static const std::regex includeRe(R"(^\s*#\s*include\s+["<]([^">]+)[">].*$)");
        static const std::regex versionRe(R"(^\s*#\s*version\b.*$)");
        std::istringstream lines(text);
        std::string line;
        int lineNo = 0;
        if (versionSeen) out << "#line 1 " << index << "\n";
        while (std::getline(lines, line)) {
            ++lineNo;
            std::smatch m;
            if (std::regex_match(line, m, versionRe)) {
                VEIL_CHECK(!versionSeen, "{}:{}: #version in an included file", path.string(),
                           lineNo);
                versionSeen = true;
                out << line << "\n";
                for (const auto& d : defines)
                    out << "#define " << d << "\n";
                out << "#line " << lineNo + 1 << " " << index << "\n";
            } else if (std::regex_match(line, m, includeRe)) {
                VEIL_CHECK(versionSeen, "{}:{}: #include before #version", path.string(), lineNo);
                process(resolve(m[1].str(), path));
                out << "#line " << lineNo + 1 << " " << index << "\n";
            } else {
                out << line << "\n";
            }
        }
        VEIL_CHECK(versionSeen, "{}: no #version directive", path.string());
        stack.pop_back();
    }
};

} // namespace

ShaderSource preprocessShader(const fs::path& file, const std::vector<std::string>& defines,
                              const fs::path& root, const IncludeAliases& aliases) {
    Preprocessor pp;
    pp.root = root;
    pp.defines = defines;
    pp.aliases = aliases;
    fs::path path = file.is_absolute() ? file : root / file;
    VEIL_CHECK(fs::exists(path),
               "shader file '{}' not found (shader folder '{}'; set "
               "VEIL_SHADER_DIR to move it)",
               path.string(), root.string());
    pp.process(fs::weakly_canonical(path));
    return {pp.out.str(), std::move(pp.files)};
}

std::string translateShaderLog(const std::string& log, const std::vector<std::string>& files) {
    // Mesa: "0:12(5): error: ..."; NVIDIA: "0(12) : error C1008: ...".
    static const std::regex mesaRe(R"(^(\d+):(\d+)\((\d+)\))");
    static const std::regex nvRe(R"(^(\d+)\((\d+)\))");
    std::istringstream in(log);
    std::ostringstream out;
    std::string line;
    auto name = [&](const std::string& n) {
        std::size_t i = std::stoul(n);
        return i < files.size() ? files[i] : "<source " + n + ">";
    };
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_search(line, m, mesaRe))
            out << name(m[1]) << ":" << m[2] << ":" << m[3] << m.suffix() << "\n";
        else if (std::regex_search(line, m, nvRe))
            out << name(m[1]) << ":" << m[2] << m.suffix() << "\n";
        else
            out << line << "\n";
    }
    return out.str();
}

std::string ProgramDesc::label() const {
    std::string s;
    for (const auto& st : stages) {
        if (!s.empty()) s.push_back('+');
        s.append(st.file.generic_string());
    }
    return s;
}

ProgramDesc ProgramDesc::graphics(fs::path vertex, fs::path fragment,
                                  std::vector<std::string> defines, IncludeAliases aliases) {
    ProgramDesc d;
    d.stages = {{GL_VERTEX_SHADER, std::move(vertex)}, {GL_FRAGMENT_SHADER, std::move(fragment)}};
    d.defines = std::move(defines);
    d.aliases = std::move(aliases);
    return d;
}

ProgramDesc ProgramDesc::compute(fs::path file, std::vector<std::string> defines,
                                 IncludeAliases aliases) {
    ProgramDesc d;
    d.stages = {{GL_COMPUTE_SHADER, std::move(file)}};
    d.defines = std::move(defines);
    d.aliases = std::move(aliases);
    return d;
}

Program::Program(const ProgramDesc& desc) : GlObject(NoCreate) {
    VEIL_CHECK(!desc.stages.empty(), "program without shader stages");
    const GLuint program = glCreateProgram();
    id_ = program; // owned from here: a throw below deletes it
    std::vector<GLuint> shaders;
    auto cleanup = [&] {
        for (GLuint s : shaders)
            glDeleteShader(s);
    };
    for (const auto& stage : desc.stages) {
        ShaderSource src =
            preprocessShader(stage.file, desc.defines, shaderDirectory(), desc.aliases);
        GLuint shader = glCreateShader(stage.type);
        shaders.push_back(shader);
        const char* text = src.text.c_str();
        glShaderSource(shader, 1, &text, nullptr);
        glCompileShader(shader);
        GLint ok = 0;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            GLint len = 0;
            glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
            std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
            glGetShaderInfoLog(shader, len, nullptr, log.data());
            cleanup();
            std::string translated = translateShaderLog(log.c_str(), src.files);
            while (!translated.empty() && (translated.back() == '\n' || translated.back() == ' '))
                translated.pop_back();
            throw Error(
                fmt::format("shader compile error in {}:\n{}", stage.file.string(), translated));
        }
        glAttachShader(program, shader);
    }
    glLinkProgram(program);
    cleanup();
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
        std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
        glGetProgramInfoLog(program, len, nullptr, log.data());
        throw Error(fmt::format("shader link error in {}: {}", desc.label(), log.c_str()));
    }
}

const Program& Program::set(const char* name, int v) const {
    glProgramUniform1i(id_, uniformLocation(name), v);
    return *this;
}
const Program& Program::set(const char* name, unsigned v) const {
    glProgramUniform1ui(id_, uniformLocation(name), v);
    return *this;
}
const Program& Program::set(const char* name, float v) const {
    glProgramUniform1f(id_, uniformLocation(name), v);
    return *this;
}
const Program& Program::set(const char* name, const glm::vec2& v) const {
    glProgramUniform2fv(id_, uniformLocation(name), 1, glm::value_ptr(v));
    return *this;
}
const Program& Program::set(const char* name, const glm::vec3& v) const {
    glProgramUniform3fv(id_, uniformLocation(name), 1, glm::value_ptr(v));
    return *this;
}
const Program& Program::set(const char* name, const glm::vec4& v) const {
    glProgramUniform4fv(id_, uniformLocation(name), 1, glm::value_ptr(v));
    return *this;
}
const Program& Program::set(const char* name, const glm::ivec2& v) const {
    glProgramUniform2iv(id_, uniformLocation(name), 1, glm::value_ptr(v));
    return *this;
}
const Program& Program::set(const char* name, const glm::ivec3& v) const {
    glProgramUniform3iv(id_, uniformLocation(name), 1, glm::value_ptr(v));
    return *this;
}
const Program& Program::set(const char* name, const glm::ivec4& v) const {
    glProgramUniform4iv(id_, uniformLocation(name), 1, glm::value_ptr(v));
    return *this;
}
const Program& Program::set(const char* name, const glm::mat3& v) const {
    glProgramUniformMatrix3fv(id_, uniformLocation(name), 1, GL_FALSE, glm::value_ptr(v));
    return *this;
}
const Program& Program::set(const char* name, const glm::mat4& v) const {
    glProgramUniformMatrix4fv(id_, uniformLocation(name), 1, GL_FALSE, glm::value_ptr(v));
    return *this;
}

ProgramHandle ProgramManager::add(ProgramDesc desc) {
    Program program(desc);
    programs_.emplace_back(std::move(desc), std::move(program));
    return ProgramHandle{programs_.size() - 1};
}

const Program& ProgramManager::get(ProgramHandle handle) const {
    VEIL_CHECK(handle.index < programs_.size(), "invalid program handle {}", handle.index);
    VEIL_CHECK(programs_[handle.index].second, "program {} was released", handle.index);
    return programs_[handle.index].second;
}

void ProgramManager::release(ProgramHandle handle) {
    if (handle.index < programs_.size()) programs_[handle.index].second = Program(NoCreate);
}

std::vector<ProgramHandle> ProgramManager::handlesFrom(std::size_t first) const {
    std::vector<ProgramHandle> h;
    for (std::size_t i = first; i < programs_.size(); ++i)
        h.push_back(ProgramHandle{i});
    return h;
}

std::size_t ProgramManager::liveCount() const {
    std::size_t n = 0;
    for (const auto& p : programs_)
        n += p.second ? 1 : 0;
    return n;
}

int ProgramManager::reloadAll(std::vector<std::string>* errors) {
    int failed = 0;
    for (auto& [desc, program] : programs_) {
        if (!program) continue; // released
        try {
            program = Program(desc);
        } catch (const Error& e) {
            ++failed;
            log::error("reload kept the previous program: {}", e.what());
            if (errors) errors->push_back(e.what());
        }
    }
    return failed;
}

} // namespace veil::gpu
