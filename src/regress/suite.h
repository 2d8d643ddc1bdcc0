// Image regression suites for `veil regress` (docs/regression.md): the JSON file, checked as
// a whole before anything is rendered, and the results of its cases.
#pragma once

#include "io/metrics.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace veil::regress {

enum class ReferenceKind { File, Technique, Cpu };

struct RegressCase {
    std::string name;  // unique, [A-Za-z0-9._-]
    std::string where; // JSON pointer of the case in the suite, for messages
    std::filesystem::path scene;
    // The case's `overrides`, then the ones made from `technique`, `camera`, `width`,
    // `height`: the scene is loaded with all of them (the strings of `veil render --set`).
    std::vector<std::string> overrides;
    std::string technique; // empty: the scene's render.oit
    ReferenceKind reference = ReferenceKind::Technique;
    std::filesystem::path referenceFile;         // File: absolute
    std::string referenceTechnique;              // Technique
    nlohmann::json referenceProperties;          // Technique: its properties (null = defaults)
    std::vector<std::string> referenceOverrides; // Technique: applied after `overrides`
    int cpuSteps = 0;                            // Cpu: march steps (0 = 2 x the scene's fog_steps)
    // Thresholds by metric name (io/metrics.h names, plus "rejected": the fraction of pixels
    // the per-pixel test rejects), in name order (JSON objects are read sorted).
    std::vector<std::pair<std::string, double>> metrics;
    int seeds = 1;          // renders with render.seed = seed, seed + 1, ...; metrics on the mean
    int referenceSeeds = 1; // the same for a Technique reference
    metrics::PixelTestOptions test;
    std::string note; // how the tolerances were derived, shown in the report

    std::string referenceLabel() const;
};

struct Suite {
    std::filesystem::path file;
    std::string sha256; // of the file's bytes: shards of other suite files are not merged
    std::string name;
    std::vector<RegressCase> cases;
};

// Reads and checks the whole suite: unknown keys, types, ranges, missing files, scenes that
// do not load with the case's overrides, unknown techniques. Every problem is a veil::Error
// "<suite file>: <JSON pointer>: <problem>". With `update`, missing reference files are
// allowed (they are about to be written).
Suite loadSuite(const std::filesystem::path& file, bool update);

// For --update, before anything renders: every stored reference's path is checked (its
// existing folders are folders, the file is absent or a regular file, the folder writable) and
// the missing folders are created (inside the suite's folder: loadSuite with `update` refused
// any other). Returns the folders created. Errors name the suite file and the case.
std::vector<std::filesystem::path> prepareReferenceFolders(const Suite& suite);

// One metric of one case.
struct MetricResult {
    std::string name;
    double value = 0.0;
    double threshold = 0.0;
    bool passed = false;
};

struct CaseResult {
    std::string name;
    std::string technique, reference, scene, note;
    // The effective overrides the scene was loaded with (RegressCase::overrides: the case's
    // own, then those from technique, camera, width, height, frame), in the case card, its
    // JSON and its image headers (veil:overrides).
    std::vector<std::string> overrides;
    int width = 0, height = 0, seeds = 1;
    bool passed = false;
    std::string error; // the case could not be rendered or compared
    std::vector<MetricResult> metrics;
    double seconds = 0.0;
    double heatScale = 0.0;
    // Report images, relative to the report folder (empty when not written).
    std::string renderPng, referencePng, diffPng;
    // With RunOptions::update: the reference file written and how it changed (not in JSON).
    std::string updated;
    nlohmann::json toJson() const;
    static CaseResult fromJson(const nlohmann::json& j);
};

} // namespace veil::regress
