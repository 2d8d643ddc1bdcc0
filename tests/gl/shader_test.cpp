// Shader loading: #include expansion, #line markers that make compile errors name the real
// file and line, and hot reload through stable program handles.
#include "gl_fixture.h"

#include "base/error.h"
#include "gpu/shader.h"
#include "support/test_support.h"

#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {
fs::path writeShader(const std::string& name, const std::string& text) {
    const fs::path dir = outputDir() / "shader_test";
    fs::create_directories(dir);
    const fs::path p = dir / name;
    std::ofstream(p) << text;
    return p;
}

const char* kVertex = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
} // namespace

class ShaderTest : public GlTest {};

TEST_F(ShaderTest, IncludeIsExpandedOnceWithLineMarkers) {
    writeShader("common.glsl", "float helper() { return 1.0; }\n");
    const fs::path main = writeShader("inc_main.frag", "#version 450 core\n"
                                                       "#include \"common.glsl\"\n"
                                                       "#include \"common.glsl\"\n"
                                                       "out vec4 c;\n"
                                                       "void main() { c = vec4(helper()); }\n");
    gpu::ShaderSource src = gpu::preprocessShader(main, {"FOO 2"}, main.parent_path());
    ASSERT_EQ(src.files.size(), 2u);
    EXPECT_NE(src.files[1].find("common.glsl"), std::string::npos);
    EXPECT_NE(src.text.find("#define FOO 2"), std::string::npos);
    EXPECT_NE(src.text.find("#line 1 1"), std::string::npos);
    // After the include, numbering resumes at line 3 of file 0.
    EXPECT_NE(src.text.find("#line 3 0"), std::string::npos);
    // The helper is defined once although included twice.
    const auto first = src.text.find("float helper()");
    EXPECT_EQ(src.text.find("float helper()", first + 1), std::string::npos);
    gpu::ProgramDesc desc;
    desc.stages = {{GL_VERTEX_SHADER, writeShader("inc.vert", kVertex)},
                   {GL_FRAGMENT_SHADER, main}};
    EXPECT_NO_THROW(gpu::Program p(desc));
}

TEST_F(ShaderTest, CompileErrorNamesIncludedFileAndLine) {
    writeShader("broken.glsl", "float ok() { return 1.0; }\n"
                               "float bad() { return undefinedThing; }\n");
    const fs::path main = writeShader("err_main.frag", "#version 450 core\n"
                                                       "#include \"broken.glsl\"\n"
                                                       "out vec4 c;\n"
                                                       "void main() { c = vec4(bad()); }\n");
    gpu::ProgramDesc desc;
    desc.stages = {{GL_VERTEX_SHADER, writeShader("err.vert", kVertex)},
                   {GL_FRAGMENT_SHADER, main}};
    try {
        gpu::Program p(desc);
        FAIL() << "expected a compile error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("broken.glsl:2"), std::string::npos) << msg;
    }
}

TEST_F(ShaderTest, TranslatesMesaAndNvidiaLogFormats) {
    const std::vector<std::string> files = {"a.frag", "b.glsl"};
    EXPECT_EQ(gpu::translateShaderLog("1:7(12): error: x\n", files), "b.glsl:7:12: error: x\n");
    EXPECT_EQ(gpu::translateShaderLog("0(3) : error C1008: y\n", files),
              "a.frag:3 : error C1008: y\n");
    EXPECT_EQ(gpu::translateShaderLog("plain line\n", files), "plain line\n");
}

TEST_F(ShaderTest, MissingIncludeAndCycleAreErrors) {
    const fs::path missing =
        writeShader("missing.frag", "#version 450 core\n#include \"nope.glsl\"\n");
    EXPECT_THROW(gpu::preprocessShader(missing, {}, missing.parent_path()), Error);
    writeShader("cycle_a.glsl", "#include \"cycle_b.glsl\"\n");
    writeShader("cycle_b.glsl", "#include \"cycle_a.glsl\"\n");
    const fs::path cyc =
        writeShader("cycle.frag", "#version 450 core\n#include \"cycle_a.glsl\"\n");
    try {
        gpu::preprocessShader(cyc, {}, cyc.parent_path());
        FAIL() << "expected an include-cycle error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
    }
    const fs::path noVersion = writeShader("noversion.frag", "void main() {}\n");
    EXPECT_THROW(gpu::preprocessShader(noVersion, {}, noVersion.parent_path()), Error);
}

TEST_F(ShaderTest, ReloadSwapsProgramBehindStableHandle) {
    const fs::path frag = writeShader("reload.frag", "#version 450 core\nout vec4 c;\n"
                                                     "void main() { c = vec4(1.0); }\n");
    gpu::ProgramManager manager;
    gpu::ProgramHandle h =
        manager.add(gpu::ProgramDesc::graphics(writeShader("reload.vert", kVertex), frag));
    const GLuint before = manager.get(h).id();
    EXPECT_EQ(manager.reloadAll(), 0);
    const GLuint after = manager.get(h).id();
    EXPECT_NE(after, 0u);
    EXPECT_FALSE(glIsProgram(before)) << "the old program must be deleted on reload";
    // A broken edit keeps the last good program.
    writeShader("reload.frag", "#version 450 core\nvoid main() { syntax error }\n");
    EXPECT_EQ(manager.reloadAll(), 1);
    EXPECT_EQ(manager.get(h).id(), after);
    EXPECT_TRUE(glIsProgram(after));
}

TEST_F(ShaderTest, ProjectShadersCompile) {
    // Every program of the frame compiles on this driver (the renderer builds them all).
    const gpu::IncludeAliases visibility{
        {"veil:light_visibility", "shadows/shadow_map/visibility.glsl"}};
    for (const char* frag : {"frame/opaque.frag", "frame/shadow.frag"})
        EXPECT_NO_THROW(
            gpu::Program(gpu::ProgramDesc::graphics("frame/mesh.vert", frag, {}, visibility)))
            << frag;
    EXPECT_NO_THROW(gpu::Program(gpu::ProgramDesc::compute("frame/tonemap.comp")));
}

} // namespace veil::test
