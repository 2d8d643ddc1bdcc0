// What every module hands the frame: its passes, declared (the model is Falcor's
// reflect/execute). A pass has a name (its GPU timer's name too), the frame resources it reads
// and writes, a scope that says when it runs, and execute(context). The frame's stages
// (pass/stage.h) hand it their passes in order; it concatenates them into one list
// (frame/pass_list.h), checks it once, runs it in order (frame::Renderer::render) or split
// over calls by scope (the viewer's tiled refinement, frame/refiner.h), and gives every pass
// the same Context.
//
// The modules below the frame (oit, shadows, fog, voxelize) include this header only; they
// never include each other or the frame.
#pragma once

#include "gpu/objects.h"
#include "gpu/pipeline_state.h"
#include "gpu/shader.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace veil::scene {
struct Scene;
}
namespace veil::shadows {
struct LightView;
}

namespace veil::pass {

// When a pass runs. The frame runs the scopes in this order; a list mixing them keeps it.
enum class Scope {
    // Once per frame from the lights' views (the shadow technique's maps). The viewer may keep
    // their results across frames (frame::ShadowStage::Reuse) and draw them in row bands
    // (Pass::executeRows).
    Lights,
    // Once per frame over the whole image (AO, the opaque image).
    Frame,
    // Per pixel of Context::region: the viewer's tiled refinement runs these once per screen
    // tile (with the margin of frame::Renderer::refineMarginPx()). Raster work is clipped by
    // the state tracker's scissor limit; a compute dispatch covers the region (or the whole
    // frame, keeping the region), and a pixel reads neighbours only within the margin.
    Pixels,
};

// The scene's objects a pass draws (Context::drawObjects).
enum class ObjectSet {
    Opaque,             // opaque materials (and binary-coverage ones, opaque inside)
    Transparent,        // coverage < 1 or transmission > 0
    OpaqueCasters,      // opaque materials of objects with "shadows": true
    TransparentCasters, // transparent materials of objects that cast shadows
};

// The name -> texture (or buffer) table of the frame's resources (debug views, `veil render
// --dump`, tests, the passes that read them). The module that writes a resource adds it: a
// getter, since targets are recreated on resize and some exist only in some frames (a null
// answer: no texture or buffer now).
class Resources {
public:
    using Getter = std::function<const gpu::Texture*()>;
    using BufferGetter = std::function<const gpu::Buffer*()>;
    void add(const std::string& name, Getter getter) { table_[name] = std::move(getter); }
    void add(const std::string& name, const gpu::Texture& texture) {
        table_[name] = [t = &texture] { return t; };
    }
    void addBuffer(const std::string& name, BufferGetter getter) {
        buffers_[name] = std::move(getter);
    }
    // The texture behind `name`, or null (not a resource with a texture, or none now).
    const gpu::Texture* texture(const std::string& name) const {
        const auto it = table_.find(name);
        return it == table_.end() ? nullptr : it->second();
    }
    // The buffer behind `name`, or null (not a resource with a buffer, or none now).
    const gpu::Buffer* buffer(const std::string& name) const {
        const auto it = buffers_.find(name);
        return it == buffers_.end() ? nullptr : it->second();
    }
    void clear() {
        table_.clear();
        buffers_.clear();
    }

private:
    std::map<std::string, Getter> table_;
    std::map<std::string, BufferGetter> buffers_;
};

// A light slice map a module needs ([Eisemann06 sec. 2, 3]): the objects of
// ObjectSet::TransparentCasters voxelized along every light view (Context::lightViews, one
// map layer per view) into `slices` slices per texel column of a `size` x `size` map, one
// map per material class, by a voxelize pass the frame adds before the module's passes
// (src/voxelize/light_slice_map.h). That pass writes the resource `name`: a buffer of the
// column-contiguous words of map (view layer, class) (32 slices a word, the layout of
// src/voxelize's pack.comp), and the texture `name`.range: local slicing's per-column near and
// far of the casters (RG32F array, one layer per view).
struct LightSliceMapRequest {
    std::string name;   // the resource
    std::string owner;  // who asks (error messages)
    std::string caster; // fragment shader (with frame/mesh.vert; defines DEPTH_PASS, LOCAL,
                        // CONSERVATIVE) that writes one class's bit masks into 8 RGBA32UI
                        // targets (uniforms shadowView, uSlices, uPass, uClass, uClasses, uClassT)
    std::string method; // "raster" or "conservative" (src/voxelize's names)
    int size = 0, views = 0, slices = 0;
    bool local = false; // slices subdivide each column's [near, far] of the casters
    // The material classes' transmittances per crossing surface for `scene` (at most 3; empty:
    // no transparent caster), asked once per run of the pass before it draws.
    std::function<std::vector<glm::vec3>(const scene::Scene&)> classes;
};

// What the frame gives every pass.
struct Context {
    int width = 0, height = 0; // the frame's image
    // The pixels of the Pixels passes, x0 y0 x1 y1 (x1, y1 exclusive): the whole frame, or a
    // refinement tile and its margin. Zero or empty means the whole frame.
    glm::ivec4 region{0};
    // The frame's state tracker: a pass applies a declared PipelineState before each of its
    // draws and clears (clears obey the colour and depth masks) and issues no raw GL state
    // calls of its own.
    gpu::StateTracker* state = nullptr;
    std::uint32_t seed = 1; // render.seed
    const Resources* resources = nullptr;
    // The frame's targets: hdrColor (RGBA16F) holds the opaque image and receives the
    // composites; depth (DEPTH_COMPONENT32F) is the opaque depth.
    const gpu::Texture* hdrColor = nullptr;
    const gpu::Texture* depth = nullptr;
    // The ambient visibility (R16F, frame/stages/ambient_occlusion.h) when render.ao is on, else
    // null.
    const gpu::Texture* ambientOcclusion = nullptr;
    // During a refinement tile, the opaque image of the whole frame (hdrColor holds it inside
    // the region only); null otherwise.
    const gpu::Texture* opaqueColor = nullptr;
    // The camera (the camera block at VEIL_UBO_CAMERA holds the same while the passes run).
    glm::mat4 viewProjection{1.0f}, projection{1.0f};
    bool orthographicCamera = false;
    const scene::Scene* scene = nullptr;
    // Every view of every shadow-casting light, fitted this frame (shadows/views.h).
    const std::vector<shadows::LightView>* lightViews = nullptr;
    // Draws the objects of `set` with `program` in use (frame/mesh.vert inputs and the
    // material uniforms of shaders/frame/material.glsl set per object; frame::drawObjects).
    std::function<void(const gpu::Program&, ObjectSet)> drawObjects;
    // The same objects for a compute shader (the compute rasterizer's setup): the triangle
    // count of each object of `set` in drawing order, and, with `program` in use, for each of
    // them the per-object uniforms drawObjects sets and its mesh's buffers bound as SSBOs
    // (VEIL_SSBO_MESH_*: positions, normals, uvs, billboard sizes as tightly packed floats,
    // indices), then dispatch(object's place in that order, its triangles).
    std::function<std::vector<std::uint32_t>(ObjectSet)> objectTriangles;
    std::function<void(const gpu::Program&, ObjectSet,
                       const std::function<void(std::uint32_t, std::uint32_t)>& dispatch)>
        dispatchObjects;
    // Binds the scene's density volumes for shaders/volume/volume_common.glsl (textures and
    // the uniforms of `program`); null when the scene has no grid volumes.
    std::function<void(const gpu::Program&)> bindMedia;
    // Sets the shadow technique's receiver uniforms on a program that includes
    // "veil:light_visibility"; null when no light casts shadows.
    std::function<void(const gpu::Program&)> prepareReceiver;
};

// One pass. Aggregate order: name, reads, writes, execute, executeRows, then the rest.
struct Pass {
    std::string name;
    std::vector<std::string> reads;
    std::vector<std::string> writes;
    std::function<void(const Context&)> execute;
    // Optional banded form of `execute` (Lights passes of a map of `rows` rows), so that a slow
    // driver need not run an expensive pass in one piece. executeRows(context, y0, y1) does
    // what execute(context) does restricted to the texel rows [y0, y1) of every layer of the
    // pass's maps; 0 <= y0 < y1 <= rows. Running it over consecutive bands [0, a), ...,
    // [z, rows) (no band skipped or repeated) leaves every resource bit for bit as one
    // execute() does. The passes still run in order (a band may read rows outside [y0, y1) of
    // what earlier passes wrote), the context is the same for every band, the state tracker's
    // scissor limit is off (a pass scissors to the band itself), and between bands the
    // resources hold partial work. Null: the pass only runs whole.
    std::function<void(const Context&, int y0, int y1)> executeRows = nullptr;
    Scope scope = Scope::Frame;
    // The pass shades with the lights (includes "veil:light_visibility"): the frame adds the
    // shadow technique's receiver resources to its reads and binds their textures first.
    bool receivesShadows = false;
    // Optional per-frame work of a Pixels pass that the tiled refinement runs in steps before
    // its first tile (execute does the same itself when needed): one step per call, true while
    // a step ran, false once nothing is left. Timed as `prepareName`.
    std::function<bool(const Context&)> prepareStep = nullptr;
    std::string prepareName = {};
};

} // namespace veil::pass
