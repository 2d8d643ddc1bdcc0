// The state behind `veil view`, without any UI: the scene file and the --set overrides the
// user's edits amount to, the renderer, the orbit camera, the errors, and the last good frame.
// The panel (viewer/ui/view_panel.h) and the scripts (viewer/view_script_run.h) drive it the
// same way.
//
// Every edit is a `key=value` override of the scene document, exactly what `veil render
// --set` takes, so "copy render command" reproduces the view. An edit rebuilds only what
// depends on it (see classifyOverride): a camera's values are the view; the values declared
// live with the scene's values (scene::EditEffect in scene/scene_values.cpp: a light's,
// a material's shading, exposure, tone map, fog steps, a grid volume's, not homogeneous
// fog's, optics) are copied into the live scene (a light or volume change recomputes the
// fog's light transmittance volumes only); render.oit replaces the OIT technique and its
// targets only; anything else (objects, shadows, fog resolution, volume files) builds a new
// renderer beside the old one, which stays if the new one fails.
// Errors never leave the viewer: they are kept in errors() and the last good frame stays.
#pragma once

#include "base/error.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "gpu/objects.h"
#include "grid/grid_preload.h"
#include "scene/scene.h"
#include "scene/scene_values.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace veil::session {

// Orbit around the camera's target: yaw/pitch/distance edited by the mouse or a script.
struct Orbit {
    glm::vec3 target{0.0f};
    float yaw = 0.0f, pitch = 0.0f, distance = 1.0f;
    void from(const scene::Camera& c);
    void apply(scene::Camera& c) const;
    // Moves the target in the view plane by (dx, dy) times the distance (each coordinate
    // clamped to +-kMaxExtent).
    void pan(float dx, float dy);
    // Bound of the target's coordinates and of the distance: the eye then stays inside the
    // +-1e6 that cameras.*.position accepts, so the copied `veil render` command parses.
    static constexpr float kMaxExtent = 5e5f;
};

// What an override of `key` invalidates.
enum class OverrideScope {
    Camera,   // cameras.*: the view only
    Live,     // a value declared live (overrideEditEffect is not Rebuild): copied in place
    Oit,      // render.oit: the OIT technique
    Size,     // render.width / render.height
    Renderer, // anything else: a new renderer
};
OverrideScope classifyOverride(const std::string& key);
// The declared edit effect (scene/scene_values.h) of the value `key` sets: render.<key>,
// volumes.N.<key>, lights.N.<key> and materials.N.<key> (or a component of one of the last
// two, lights.0.color.1); Rebuild for any other key.
scene::EditEffect overrideEditEffect(const std::string& key);

class ViewSession {
public:
    // Loads `scenePath` (a scene .json or a bare .vdb) with `overrides`; throws veil::Error
    // when the first scene cannot be loaded or rendered at all (nothing to show yet).
    ViewSession(const gpu::ContextInfo& context, std::filesystem::path scenePath,
                std::vector<std::string> overrides, std::string camera, int width, int height);
    ~ViewSession();
    ViewSession(const ViewSession&) = delete;
    ViewSession& operator=(const ViewSession&) = delete;

    // Each returns false (and records the error) when the change could not be made; the
    // session then keeps what it had.
    bool set(const std::string& keyValue); // "key=value" (--set syntax)
    // set("time.frame=N") for the timeline, with `grids` the frame's read-ahead (its
    // conversions made for this GPU): a frame of the same structure replaces only the
    // volumes' data, camera and lights in the renderer (frame::Renderer::replaceVolumes, as
    // `veil render --frames`; the image equals a renderer built for the frame); another one
    // builds the renderer with the grids preloaded.
    bool showFrame(int frame, const std::vector<volume::PreloadedGrid>& grids);
    bool open(const std::filesystem::path& path);        // another scene or .vdb
    bool selectOit(const std::string& name);             // render.oit = {"type": name}
    bool selectShadows(const std::string& name);         // render.shadows = {"type": name}
    bool selectCamera(const std::string& name);          // one of the scene's cameras
    bool resize(int width, int height);                  // frame size
    bool reloadShaders();                                // from disk; failures keep the old
    bool saveSceneAs(const std::filesystem::path& path); // document + overrides + camera

    void orbitBy(float dyaw, float dpitch, float zoom); // zoom: distance factor
    void panBy(float dx, float dy);
    void resetCamera(); // back to the scene's camera

    // Renders one frame; on failure the error is recorded and the last good frame stays
    // (displayTexture()). Returns whether a new frame was made. With refineTilePx() > 0 and
    // `refine` (the viewer passes false for its reduced-size frames while the camera moves) a
    // frame larger than one tile is refined in tiles instead (frame::Renderer::
    // beginRefinement): this call runs the frame's per-frame passes and returns false, each
    // refineStep() one tile; displayTexture() keeps the last complete image until then.
    bool renderFrame(bool refine = true);
    // One tile of the refinement in progress; true when that completed the frame (the display
    // then shows it). A failure is recorded as for renderFrame() and ends the refinement.
    bool refineStep();
    // The progressive bake of the fog's scattered-light cache (off by default: each frame has
    // the whole bake; the interactive window turns it on, scripted runs keep it off so that
    // their frames do not depend on timing): after a light, ambient or volume edit each frame
    // bakes for render.fog_scattered_light_budget_ms and draws with the paths so far.
    void setProgressiveBake(bool on) { progressiveBake_ = on; }
    bool progressiveBake() const { return progressiveBake_; }
    // The cache is still converging: frames render in one piece meanwhile and each moves
    // version() on, so that the window draws the next.
    bool scatteredLightConverging() const;
    bool refining() const { return renderer_->refining(); }
    // The refinement's tile size in pixels (0: every frame in one piece, the default); a
    // change renders the frame again.
    void setRefineTilePx(int px);
    // view.refine_budget_ms (0: every step takes a whole refineTilePx() tile): the pass time a
    // refinement's tile step should stay under. Each step's tile is halved (frame::Renderer::
    // refineStep's maxTilePx) until its estimated pass time fits, down to kMinRefineTilePx:
    // estimated from the pass time per pixel of the last step (tile and margin) of the same
    // renderer, technique and frame size; unknown (a new one), the step takes the smallest tile.
    void setRefineBudgetMs(double ms);
    double refineBudgetMs() const { return refineBudgetMs_; }
    static constexpr int kMinRefineTilePx = 16;
    // The tile size the next step would take (refineTilePx() when the budget is off).
    int nextRefineTilePx() const;
    // view.reuse_shadow_maps (on by default): frames keep the shadow technique's maps while
    // nothing they depend on changed (frame::Renderer::setReuseShadowMaps; every edit that
    // can alter them redraws them, a camera move does not).
    void setReuseShadowMaps(bool on);
    bool reusesShadowMaps() const { return reuseShadowMaps_; }
    int refineTilePx() const { return refineTilePx_; }
    // What the refinements did per UI frame (endUiFrame() closes one): tests check that no UI
    // frame ran the per-pixel passes over more than one tile.
    struct RefineLog {
        int tilePx = 0, tiles = 0; // of the last refinement begun (its grid)
        int steps = 0;             // its tile steps so far (a tile split by the budget: its parts)
        int minTilePx = 0;         // the smallest tile side a step took (the budget's halving)
        int uiFrames = 0;          // UI frames it has spanned so far (its begin included)
        int maxTilesPerUiFrame = 0;
        // Light transmittance slabs (frame::Renderer::kRefineLightSlabTexels z slices of one
        // volume) computed by it, and the most in one UI frame.
        int lightSlabs = 0, maxLightSlabsPerUiFrame = 0;
        // Shadow bands (frame::Renderer::kRefineShadowBandTexels, or an unbanded shadow pass)
        // run by its steps, and the most per-frame steps (a band, or the AO and opaque passes)
        // in one UI frame.
        int shadowSteps = 0, maxPerFrameStepsPerUiFrame = 0;
        // The most pixels the per-pixel passes covered in one UI frame (a tile and its margin).
        long long maxPixelsPerUiFrame = 0;
        // Pass times (reported, never asserted): the first UI frame's (the per-frame passes),
        // the longest of the tiles' UI frames, the longest UI frame of all, and all together.
        double firstUiFrameMs = 0.0, maxTileUiFrameMs = 0.0, maxUiFrameMs = 0.0, totalMs = 0.0;
        bool complete = false;
        int completed = 0; // refinements completed since the start
    };
    const RefineLog& refineLog() const { return refineLog_; }
    void endUiFrame();

    const frame::Renderer& renderer() const { return *renderer_; }
    frame::Renderer& renderer() { return *renderer_; }
    const scene::Scene& scene() const { return *scene_; }
    const std::filesystem::path& scenePath() const { return scenePath_; }
    const std::string& cameraName() const { return cameraName_; }
    const scene::Camera& camera() const { return camera_; }
    const std::vector<std::string>& overrides() const { return overrides_; }
    // The LDR image of the last frame that rendered (RGBA8, frame size).
    const gpu::Texture& displayTexture() const { return display_; }
    int frameWidth() const { return width_; }
    int frameHeight() const { return height_; }

    // The `veil render` line that renders this view: scene, --width/--height, --camera and
    // every override, with the camera's position/target/up as cameras.N.* overrides.
    std::string renderCommand(const std::string& output = "out.png") const;
    // The same as arguments (for running it without a shell in tests).
    std::vector<std::string> renderArguments(const std::string& output) const;

    // Errors so far (newest last) and the one of the last change or frame ("" = fine).
    const std::vector<std::string>& errors() const { return errors_; }
    const std::string& lastError() const { return lastError_; }
    const std::string& status() const { return status_; }
    void setStatus(std::string s) { status_ = std::move(s); }
    void fail(const std::string& what); // records an error from outside (file dialog, ...)
    bool frameFailed() const { return frameFailed_; }
    // Whether the OIT technique named is usable here (greyed out otherwise).
    bool oitAvailable(const std::string& name) const;
    bool shadowsAvailable(const std::string& name) const;
    const gpu::ContextInfo& context() const { return context_; }
    // Counts every change that needs a new frame (edits, camera moves, resizes, opens).
    std::uint64_t version() const { return version_; }
    // Counts the new scenes + renderers built (a file opened, an edit past the live paths) and
    // the in-place light/volume value edits (what a second renderer of the same scene, the
    // error view's reference, must follow).
    std::uint64_t rebuilds() const { return rebuilds_; }
    std::uint64_t valueChanges() const { return valueChanges_; }
    // Timeline frames shown by replacing the volumes' data (showFrame) rather than rebuilding.
    std::uint64_t framesReplaced() const { return framesReplaced_; }
    // The scene document as read from the .json (null for a bare .vdb), before overrides.
    const nlohmann::json& sourceDocument() const { return sourceDoc_; }

private:
    struct Built; // a scene and its renderer
    // The scene of `path` with `overrides` (json or vdb).
    std::unique_ptr<scene::Scene> loadWith(const std::filesystem::path& path,
                                           const std::vector<std::string>& overrides) const;
    // loadWith() plus the viewer's defaults, added to `overrides` (reference: pool_overflow
    // = drop).
    std::unique_ptr<scene::Scene> loadWithDefaults(const std::filesystem::path& path,
                                                   std::vector<std::string>& overrides) const;
    // Builds a new scene + renderer; on success replaces the current ones.
    void rebuild(const std::filesystem::path& path, std::vector<std::string>& overrides);
    void adoptCamera(bool resetOrbit);
    void addOverride(std::vector<std::string>& list, const std::string& keyValue) const;
    std::vector<std::string> cameraOverrides() const;
    void copyToDisplay();
    bool succeed(const std::string& what);
    bool record(const std::string& error);

    gpu::ContextInfo context_;
    std::filesystem::path scenePath_;
    std::vector<std::string> overrides_;
    std::string cameraName_;
    int width_ = 0, height_ = 0;
    std::unique_ptr<scene::Scene> scene_;
    std::unique_ptr<frame::Renderer> renderer_;
    scene::Camera camera_;
    Orbit orbit_;
    bool orbited_ = false; // false: the scene's camera exactly, as `veil render` has it
    gpu::Texture display_{gpu::NoCreate};
    std::vector<std::string> errors_;
    std::string lastError_, status_;
    bool frameFailed_ = false;
    int refineTilePx_ = 0;
    double refineBudgetMs_ = 0.0;
    bool progressiveBake_ = false;
    // The refinement's estimate (refineBudgetMs()): pass ms per pixel of the last tile step, and
    // what it holds for (renderer, techniques, frame size); < 0 = none.
    double refineMsPerPixel_ = -1.0;
    std::string refineEstimateKey_;
    std::string refineKey() const;
    // A frame or refinement step threw: recorded, the refinement ended, the last good frame
    // stays until the next change; returns false.
    bool frameFailed(const Error& e);
    bool reuseShadowMaps_ = true;
    RefineLog refineLog_;
    int uiFrameTiles_ = 0;         // tiles refined since the last endUiFrame()
    int uiFrameLightSlabs_ = 0;    // light transmittance slabs since the last endUiFrame()
    int uiFramePerFrameSteps_ = 0; // shadow bands and per-frame pass steps since then
    long long uiFramePixels_ = 0;  // per-pixel pass pixels since then
    bool uiFrameRefines_ = false;  // a refinement ran (begun or stepped) in this UI frame
    double uiFrameMs_ = 0.0;       // its pass times
    std::uint64_t version_ = 0, rebuilds_ = 0, valueChanges_ = 0, framesReplaced_ = 0;
    nlohmann::json sourceDoc_;
};

} // namespace veil::session
