// Shader programs from files in shaders/: `#include "path"` is expanded by the loader (each
// file once), `#line L N` markers keep line numbers, and compile logs are rewritten from
// source-string numbers to file names, so an error names the real file and line (nvpro's
// shaderfilemanager is the model). Programs are handed out as stable handles by
// ProgramManager so a hot reload swaps the GL program underneath its users.
#pragma once

#include "gpu/gl_object.h"

#include <glm/glm.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace veil::gpu {

// Root of the shader tree: $VEIL_SHADER_DIR if set, else an installed tree's
// share/veil/shaders beside the executable (bin/../share/veil/shaders), else the source
// tree's shaders/.
std::filesystem::path shaderDirectory();

struct ShaderSource {
    std::string text;
    std::vector<std::string> files; // files[i] is the file of GLSL source-string number i
};

// Expands includes starting from `file` (relative to `root` or absolute). Includes resolve
// against the including file's folder first, then `root`. `defines` ("NAME" or "NAME VALUE")
// are inserted after #version. Throws veil::Error for missing files, a missing #version or
// an include cycle.
// `aliases` maps virtual include names to files, so that `#include "veil:oit_emit"` pulls in
// the emission function of whichever OIT technique the program is built for.
using IncludeAliases = std::vector<std::pair<std::string, std::filesystem::path>>;
ShaderSource preprocessShader(const std::filesystem::path& file,
                              const std::vector<std::string>& defines,
                              const std::filesystem::path& root = shaderDirectory(),
                              const IncludeAliases& aliases = {});

// Rewrites "N:L(C)" (Mesa) and "N(L)" (NVIDIA) prefixes of a compile log to "file:L".
std::string translateShaderLog(const std::string& log, const std::vector<std::string>& files);

struct ProgramTraits {
    static void destroy(GLuint id) { glDeleteProgram(id); }
};

struct ShaderStage {
    GLenum type; // GL_VERTEX_SHADER, ...
    std::filesystem::path file;
};

struct ProgramDesc {
    std::vector<ShaderStage> stages;
    std::vector<std::string> defines;
    IncludeAliases aliases;
    std::string label() const;

    static ProgramDesc graphics(std::filesystem::path vertex, std::filesystem::path fragment,
                                std::vector<std::string> defines = {}, IncludeAliases aliases = {});
    static ProgramDesc compute(std::filesystem::path file, std::vector<std::string> defines = {},
                               IncludeAliases aliases = {});
};

class Program : public GlObject<ProgramTraits> {
public:
    using GlObject::GlObject;
    // Compiles and links; throws veil::Error with the translated log on failure.
    explicit Program(const ProgramDesc& desc);

    void use() const { glUseProgram(id_); }
    GLint uniformLocation(const char* name) const { return glGetUniformLocation(id_, name); }
    // Setters ignore uniforms the compiler removed (location -1), as GL does.
    const Program& set(const char* name, int v) const;
    const Program& set(const char* name, unsigned v) const;
    const Program& set(const char* name, float v) const;
    const Program& set(const char* name, const glm::vec2& v) const;
    const Program& set(const char* name, const glm::vec3& v) const;
    const Program& set(const char* name, const glm::vec4& v) const;
    const Program& set(const char* name, const glm::ivec2& v) const;
    const Program& set(const char* name, const glm::ivec3& v) const;
    const Program& set(const char* name, const glm::ivec4& v) const;
    const Program& set(const char* name, const glm::mat3& v) const;
    const Program& set(const char* name, const glm::mat4& v) const;
};

// Stable program ids: get(handle) always returns the current program for that handle.
struct ProgramHandle {
    std::size_t index = static_cast<std::size_t>(-1);
    bool valid() const { return index != static_cast<std::size_t>(-1); }
};

class ProgramManager {
public:
    ProgramHandle add(ProgramDesc desc);
    const Program& get(ProgramHandle handle) const;
    // Deletes the program of `handle` (a replaced OIT technique's); get() of it then throws,
    // reloadAll() skips it. Handles stay stable: its slot is kept, empty.
    void release(ProgramHandle handle);
    // Handles added from `first` on (what one step, e.g. creating a technique, added).
    std::vector<ProgramHandle> handlesFrom(std::size_t first) const;
    std::size_t size() const { return programs_.size(); }
    // Programs that exist (added and not released).
    std::size_t liveCount() const;
    // Recompiles every program from its files. A program that fails keeps its previous
    // version; returns the number that failed (their errors are logged).
    int reloadAll(std::vector<std::string>* errors = nullptr);
    // What every program was built from, in order of add() (tests: which files are compiled).
    std::vector<ProgramDesc> descriptions() const {
        std::vector<ProgramDesc> d;
        for (const auto& p : programs_)
            if (p.second) d.push_back(p.first);
        return d;
    }

private:
    std::vector<std::pair<ProgramDesc, Program>> programs_;
};

} // namespace veil::gpu
