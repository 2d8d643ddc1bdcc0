// Shadow volumes (src/shadows/volume): the casters' triangle ranges and the per-light indirect
// commands that compact.comp writes and silhouette.comp consumes (layout mirrored by
// kDrawHeader in src/shadows/volume/volume.cpp).
#include "../../common/bindings.h"

struct CasterRange {
    uint firstTriangle; // into adjacency[] (6 indices each)
    uint triangles;
    uint closed; // 1: closed 2-manifold (silhouettes), 0: per-triangle prisms
    uint pad;
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_RANGES) readonly buffer Ranges {
    CasterRange ranges[];
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_DRAW) coherent buffer Draw {
    // DrawArraysIndirectCommand of the depth-fail volumes: triangles[0, drawCount)
    uint drawCount, drawInstances, drawFirst, drawBase;
    uint groupsX, groupsY, groupsZ; // DispatchIndirectCommand of silhouette.comp
    uint submitted;                 // caster triangles launched (the surviving casters')
    uint survivors;                 // entries of work[]
    uint silhouetteEdges;           // side quads of closed casters
    uint fanTriangles;              // back-cap fan triangles of clamped closed casters
    uint passTriangles;             // triangles of depth-pass volumes
    // DrawArraysIndirectCommand of the depth-pass volumes, filled from the end of triangles[]
    // down: triangles[passFirst, capacity)
    uint passCount, passInstances, passFirst, passBase;
    uvec2 work[]; // per surviving caster: caster, its first thread (prefix of triangles)
};
