// A stage of the frame: one module's part of it, in the frame's ordered list of stages
// (frame::Renderer: shadows, depth pre-pass, AO, opaque, fog, transparency, tonemap). The frame
// knows its stages only through this interface: it asks each, in order, for its passes
// (pass.h) and the resources it publishes, sums their GPU bytes, hands them a new frame size,
// and lets each fill its part of the per-frame pass::Context. Adding a pass to the frame is
// adding a stage (docs/architecture.md "Adding a stage": a copy of the stage template in
// src/frame/stages/), not editing the frame.
#pragma once

#include "pass/pass.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace veil::pass {

// What the frame tells a stage while it assembles the pass list: the resources the stages
// before it write (and the frame's own: depth, hdr, ldr), so that a stage reads what exists
// (the opaque pass reads ao.visibility only when an AO stage wrote it).
struct Assembly {
    std::vector<std::string> written;
    bool has(const std::string& resource) const {
        return std::find(written.begin(), written.end(), resource) != written.end();
    }
};

class Stage {
public:
    virtual ~Stage() = default;
    Stage() = default;
    Stage(const Stage&) = delete;
    Stage& operator=(const Stage&) = delete;

    // The stage's name in the frame's list (insertion points, messages): "shadows", "opaque".
    virtual std::string name() const = 0;
    // Its passes in frame order, asked again whenever the frame rebuilds its list.
    virtual std::vector<Pass> passes(const Assembly& assembly) = 0;
    // The textures and buffers behind the resources its passes write (getters: targets are
    // recreated on resize).
    virtual void addResources(Resources& /*resources*/) const {}
    // GPU memory it holds (reports).
    virtual std::size_t gpuBytes() const { return 0; }
    // The frame's targets (context.width, height, hdrColor, depth) were created or resized.
    virtual void resize(Context& /*context*/) {}
    // Once per frame before the first pass, in stage order: per-frame uniforms, and the
    // context members the stage provides (lightViews, prepareReceiver, ambientOcclusion,
    // bindMedia).
    virtual void beginFrame(Context& /*context*/) {}
};

} // namespace veil::pass
