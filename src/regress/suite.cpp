#include "regress/suite.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/sha256.h"
#include "base/text.h"
#include "oit/technique.h"
#include "regress/report_folder.h"
#include "scene/json_text.h"
#include "scene/scene.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace veil::regress {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kCaseKeys{"name",
                                         "scene",
                                         "overrides",
                                         "technique",
                                         "camera",
                                         "width",
                                         "height",
                                         "reference",
                                         "reference_properties",
                                         "reference_overrides",
                                         "cpu_steps",
                                         "metrics",
                                         "seeds",
                                         "reference_seeds",
                                         "alpha",
                                         "correction",
                                         "note",
                                         "frame"};

// Errors name the suite file and the JSON pointer of the value.
struct Where {
    std::string file;
    [[noreturn]] void fail(const std::string& pointer, const std::string& problem) const {
        if (pointer.empty()) throw Error(fmt::format("{}: {}", file, problem));
        throw Error(fmt::format("{}: {}: {}", file, pointer, problem));
    }
};

std::string typeName(const nlohmann::json& v) { return v.type_name(); }

int intIn(const Where& w, const std::string& p, const nlohmann::json& v, long lo, long hi) {
    double d = 0.0;
    if (v.is_number_integer() || v.is_number_unsigned())
        d = double(v.get<long long>());
    else if (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>())
        d = v.get<double>();
    else
        w.fail(p,
               fmt::format("expected an integer, got {}", v.is_number() ? v.dump() : typeName(v)));
    if (d < double(lo) || d > double(hi))
        w.fail(p, fmt::format("value {} out of range [{}, {}]", v.dump(), lo, hi));
    return static_cast<int>(d);
}

std::string str(const Where& w, const std::string& p, const nlohmann::json& v) {
    if (!v.is_string()) w.fail(p, "expected a string, got " + typeName(v));
    const std::string s = v.get<std::string>();
    if (s.empty()) w.fail(p, "must not be empty");
    return s;
}

double number(const Where& w, const std::string& p, const nlohmann::json& v) {
    if (!v.is_number()) w.fail(p, "expected a number, got " + typeName(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) w.fail(p, "must be finite");
    return d;
}

// One case: `c` merged over `defaults` (the case's own keys win).
RegressCase parseCase(const Where& w, const fs::path& dir, const nlohmann::json& c,
                      const nlohmann::json& defaults, const std::string& casePtr, bool update) {
    if (!c.is_object()) w.fail(casePtr, "expected an object, got " + typeName(c));
    nlohmann::json merged = defaults;
    for (auto it = c.begin(); it != c.end(); ++it)
        merged[it.key()] = it.value();
    auto ptr = [&](const std::string& key) {
        return (c.contains(key) ? casePtr : std::string("/defaults")) + "/" + key;
    };
    for (auto it = merged.begin(); it != merged.end(); ++it)
        if (std::find(kCaseKeys.begin(), kCaseKeys.end(), it.key()) == kCaseKeys.end())
            w.fail(ptr(it.key()),
                   fmt::format("unknown key (known: {})", fmt::join(kCaseKeys, ", ")));
    RegressCase k;
    k.where = casePtr;
    if (!merged.contains("name")) w.fail(casePtr, "missing key 'name'");
    k.name = str(w, ptr("name"), merged["name"]);
    if (!validCaseName(k.name))
        w.fail(ptr("name"), fmt::format("'{}': use letters, digits, '-', '_' and '.', not "
                                        "starting with '.' (it names files of the report)",
                                        printable(k.name, 100)));
    if (!merged.contains("scene")) w.fail(casePtr, "missing key 'scene'");
    k.scene = (dir / str(w, ptr("scene"), merged["scene"])).lexically_normal();
    if (!fs::is_regular_file(k.scene))
        w.fail(ptr("scene"), fmt::format("scene file '{}' does not exist", k.scene.string()));
    if (merged.contains("overrides")) {
        const auto& o = merged["overrides"];
        if (!o.is_array())
            w.fail(ptr("overrides"), "expected an array of strings, got " + typeName(o));
        for (std::size_t i = 0; i < o.size(); ++i)
            k.overrides.push_back(str(w, ptr("overrides") + "/" + std::to_string(i), o[i]));
    }
    std::vector<std::string> derived;
    if (merged.contains("technique")) {
        const auto& t = merged["technique"];
        if (t.is_string()) {
            k.technique = str(w, ptr("technique"), t);
            derived.push_back("render.oit=" + nlohmann::json(k.technique).dump());
        } else if (t.is_object()) {
            if (!t.contains("type")) w.fail(ptr("technique"), "an object technique needs 'type'");
            k.technique = str(w, ptr("technique") + "/type", t["type"]);
            derived.push_back("render.oit=" + t.dump());
        } else
            w.fail(ptr("technique"),
                   "expected a technique name or {\"type\": NAME, ...}, got " + typeName(t));
        if (!oit::Registry::instance().find(k.technique))
            w.fail(ptr("technique"),
                   fmt::format("unknown OIT technique '{}' (known: {})",
                               printable(k.technique, 100),
                               fmt::join(oit::Registry::instance().names(), ", ")));
    }
    if (merged.contains("camera"))
        derived.push_back("render.camera=" +
                          nlohmann::json(str(w, ptr("camera"), merged["camera"])).dump());
    for (const char* key : {"width", "height"})
        if (merged.contains(key))
            derived.push_back(std::string("render.") + key + "=" +
                              std::to_string(intIn(w, ptr(key), merged[key], 1, 16384)));
    // Animated scenes: the frame to render (time.frame).
    if (merged.contains("frame"))
        derived.push_back("time.frame=" + std::to_string(intIn(w, ptr("frame"), merged["frame"],
                                                               -(1 << 30), 1 << 30)));
    if (merged.contains("seeds")) k.seeds = intIn(w, ptr("seeds"), merged["seeds"], 1, 1024);
    if (merged.contains("reference_seeds"))
        k.referenceSeeds = intIn(w, ptr("reference_seeds"), merged["reference_seeds"], 1, 1024);
    if (merged.contains("cpu_steps"))
        k.cpuSteps = intIn(w, ptr("cpu_steps"), merged["cpu_steps"], 1, 65536);
    if (merged.contains("alpha")) {
        k.test.alpha = number(w, ptr("alpha"), merged["alpha"]);
        if (!(k.test.alpha > 0.0 && k.test.alpha < 1.0))
            w.fail(ptr("alpha"), fmt::format("significance level {} not in (0, 1)", k.test.alpha));
    }
    if (merged.contains("correction")) {
        const std::string s = str(w, ptr("correction"), merged["correction"]);
        if (s == "holm")
            k.test.correction = metrics::Correction::Holm;
        else if (s == "bonferroni")
            k.test.correction = metrics::Correction::Bonferroni;
        else
            w.fail(ptr("correction"),
                   fmt::format("'{}': use holm or bonferroni", printable(s, 100)));
    }
    if (merged.contains("note")) {
        if (!merged["note"].is_string()) w.fail(ptr("note"), "expected a string");
        k.note = merged["note"].get<std::string>();
    }

    // The reference: a stored image, "cpu", or a technique name.
    if (!merged.contains("reference")) w.fail(casePtr, "missing key 'reference'");
    const std::string ref = str(w, ptr("reference"), merged["reference"]);
    if (lowerExtension(ref) == ".exr") {
        k.reference = ReferenceKind::File;
        k.referenceFile = (dir / ref).lexically_normal();
        // --update writes the file (and the folders it needs) inside the suite's folder only.
        if (update) try {
                safePathInside(dir, ref, "reference");
            } catch (const Error& e) {
                w.fail(ptr("reference"), std::string(e.what()) +
                                             ": --update writes references only inside the "
                                             "suite's folder");
            }
        if (!update && !fs::is_regular_file(k.referenceFile))
            w.fail(ptr("reference"), fmt::format("reference image '{}' does not exist (veil "
                                                 "regress --update writes it)",
                                                 k.referenceFile.string()));
    } else if (ref == "cpu") {
        k.reference = ReferenceKind::Cpu;
    } else {
        k.reference = ReferenceKind::Technique;
        k.referenceTechnique = ref;
        if (!oit::Registry::instance().find(ref))
            w.fail(ptr("reference"),
                   fmt::format(
                       "'{}' is not a .exr file, 'cpu' or a known OIT technique (known: {})",
                       printable(ref, 100), fmt::join(oit::Registry::instance().names(), ", ")));
    }
    if (merged.contains("reference_properties")) {
        if (k.reference != ReferenceKind::Technique)
            w.fail(ptr("reference_properties"), "only for a technique reference");
        if (!merged["reference_properties"].is_object())
            w.fail(ptr("reference_properties"), "expected an object");
        k.referenceProperties = merged["reference_properties"];
    }
    if (merged.contains("reference_overrides")) {
        const auto& o = merged["reference_overrides"];
        if (k.reference != ReferenceKind::Technique)
            w.fail(ptr("reference_overrides"), "only for a technique reference");
        if (!o.is_array())
            w.fail(ptr("reference_overrides"), "expected an array of strings, got " + typeName(o));
        for (std::size_t i = 0; i < o.size(); ++i)
            k.referenceOverrides.push_back(
                str(w, ptr("reference_overrides") + "/" + std::to_string(i), o[i]));
    }
    if (k.cpuSteps && k.reference != ReferenceKind::Cpu)
        w.fail(ptr("cpu_steps"), "only for the reference \"cpu\"");
    if (k.referenceSeeds > 1 && k.reference != ReferenceKind::Technique)
        w.fail(ptr("reference_seeds"), "only for a technique reference");

    // Metrics and their tolerances.
    if (!merged.contains("metrics")) w.fail(casePtr, "missing key 'metrics'");
    const auto& m = merged["metrics"];
    if (!m.is_object() || m.empty())
        w.fail(ptr("metrics"), "expected an object of metric: tolerance, e.g. {\"rmse\": 0.003}");
    for (auto it = m.begin(); it != m.end(); ++it) {
        const std::string p = ptr("metrics") + "/" + it.key();
        if (!metrics::isMetricName(it.key()) && it.key() != "rejected")
            w.fail(p, fmt::format("unknown metric (known: {}, rejected)",
                                  fmt::join(metrics::metricNames(), ", ")));
        const double t = number(w, p, it.value());
        if (it.key() == "ssim" && !(t > -1.0 && t <= 1.0))
            w.fail(p, fmt::format("SSIM tolerance {} not in (-1, 1]", t));
        else if (it.key() == "rejected" && !(t >= 0.0 && t <= 1.0))
            w.fail(p, fmt::format("rejected-pixel fraction {} not in [0, 1]", t));
        else if (it.key() != "psnr" && it.key() != "ssim" && t < 0.0)
            w.fail(p, fmt::format("tolerance {} must be >= 0", t));
        if (it.key() == "rejected" && k.seeds < 2 && k.referenceSeeds < 2)
            w.fail(p, "the per-pixel test needs \"seeds\" >= 2 (renders with different seeds)");
        k.metrics.emplace_back(it.key(), t);
    }

    // The scene must load with the case's overrides, and the technique's properties must be
    // valid, before anything is rendered.
    k.overrides.insert(k.overrides.end(), derived.begin(), derived.end());
    try {
        const scene::Scene s = scene::loadScene(k.scene, k.overrides);
        oit::Registry::instance().resolve(s.render.oit, s.render.oitProperties, s.render.oitWhere);
        if (k.reference == ReferenceKind::Technique && !k.referenceOverrides.empty()) {
            std::vector<std::string> all = k.overrides;
            all.insert(all.end(), k.referenceOverrides.begin(), k.referenceOverrides.end());
            scene::loadScene(k.scene, all);
        }
        if (k.reference == ReferenceKind::Technique)
            oit::Registry::instance().resolve(k.referenceTechnique, k.referenceProperties,
                                              ptr("reference_properties"));
        if (k.reference == ReferenceKind::Cpu) {
            if (!s.objects.empty())
                w.fail(ptr("reference"),
                       fmt::format("the CPU fog reference draws no surfaces, but scene '{}' has {} "
                                   "object(s): add the override \"objects=[]\"",
                                   k.scene.string(), s.objects.size()));
            if (s.volumes.empty())
                w.fail(ptr("reference"), "the CPU fog reference needs a scene with volumes");
        }
    } catch (const Error& e) {
        const std::string msg = e.what();
        if (msg.rfind(w.file + ":", 0) == 0) throw;
        w.fail(ptr("scene"), msg);
    }
    return k;
}

} // namespace

std::string RegressCase::referenceLabel() const {
    switch (reference) {
    case ReferenceKind::File:
        return referenceFile.filename().string();
    case ReferenceKind::Cpu:
        return "cpu (CPU fog reference)";
    case ReferenceKind::Technique:
        break;
    }
    return referenceSeeds > 1 ? fmt::format("{} ({} seeds)", referenceTechnique, referenceSeeds)
                              : referenceTechnique;
}

Suite loadSuite(const fs::path& file, bool update) {
    const Where w{file.string()};
    std::error_code ec;
    const fs::file_status st = fs::status(file, ec);
    if (fs::is_directory(st)) {
        std::vector<std::string> json;
        for (const auto& e : fs::directory_iterator(file, ec))
            if (e.path().extension() == ".json") json.push_back(e.path().filename().string());
        std::sort(json.begin(), json.end());
        if (json.size() > 4) json.resize(4), json.push_back("...");
        throw Error(fmt::format(
            "suite '{}' is a folder: give a suite file (JSON with \"cases\", "
            "docs/regression.md){}",
            file.string(),
            json.empty() ? std::string("; the folder holds no .json file")
                         : fmt::format("; JSON files there: {}", fmt::join(json, ", "))));
    }
    VEIL_CHECK(!fs::exists(st) || fs::is_regular_file(st),
               "cannot read suite file '{}': not a regular file (a device, FIFO or socket)",
               file.string());
    std::ifstream in(file, std::ios::binary);
    VEIL_CHECK(in, "cannot open suite file '{}'", file.string());
    std::stringstream ss;
    ss << in.rdbuf();
    // The parser shared with scenes: comments, a nesting cap (kMaxJsonDepth) and no duplicate
    // keys, errors naming the file and the JSON pointer.
    const nlohmann::json doc = scene::parseJsonText(ss.str(), file.string());
    if (!doc.is_object()) w.fail("", "expected an object with \"cases\"");
    for (auto it = doc.begin(); it != doc.end(); ++it)
        if (it.key() != "name" && it.key() != "cases" && it.key() != "defaults")
            w.fail("/" + it.key(), "unknown key (known: name, defaults, cases)");
    Suite suite;
    suite.file = fs::absolute(file).lexically_normal();
    suite.sha256 = sha256Hex(ss.str());
    suite.name = doc.contains("name") ? str(w, "/name", doc["name"]) : file.stem().string();
    const nlohmann::json defaults = doc.value("defaults", nlohmann::json::object());
    if (!defaults.is_object()) w.fail("/defaults", "expected an object");
    if (defaults.contains("name")) w.fail("/defaults/name", "a name belongs to one case");
    if (!doc.contains("cases") || !doc["cases"].is_array() || doc["cases"].empty())
        w.fail("/cases", "expected a non-empty array of cases");
    std::set<std::string> names;
    std::set<fs::path> written;
    for (std::size_t i = 0; i < doc["cases"].size(); ++i) {
        const std::string p = "/cases/" + std::to_string(i);
        RegressCase k =
            parseCase(w, suite.file.parent_path(), doc["cases"][i], defaults, p, update);
        if (!names.insert(k.name).second)
            w.fail(p + "/name", fmt::format("case name '{}' is used twice", k.name));
        if (k.reference == ReferenceKind::File && !written.insert(k.referenceFile).second)
            w.fail(p + "/reference", fmt::format("reference '{}' is used by two cases (--update "
                                                 "would write it twice)",
                                                 k.referenceFile.string()));
        suite.cases.push_back(std::move(k));
    }
    return suite;
}

std::vector<fs::path> prepareReferenceFolders(const Suite& suite) {
    std::vector<fs::path> missing;
    for (const RegressCase& k : suite.cases) {
        if (k.reference != ReferenceKind::File) continue;
        const std::string where = fmt::format("{}: {}/reference", suite.file.string(), k.where);
        // Every part of the folder that exists must be a folder; the rest is created.
        for (fs::path d = k.referenceFile.parent_path(); !d.empty(); d = d.parent_path()) {
            std::error_code ec;
            const fs::file_status st = fs::status(d, ec);
            if (fs::exists(st)) {
                VEIL_CHECK(fs::is_directory(st),
                           "{}: cannot write reference '{}': '{}' exists and is not a folder",
                           where, k.referenceFile.string(), d.string());
                break;
            }
            if (std::find(missing.begin(), missing.end(), d) == missing.end()) missing.push_back(d);
            if (d == d.parent_path()) break;
        }
        std::error_code ec;
        const fs::file_status st = fs::status(k.referenceFile, ec);
        VEIL_CHECK(!fs::exists(st) || fs::is_regular_file(st),
                   "{}: cannot write reference '{}': it exists and is not a regular file", where,
                   k.referenceFile.string());
    }
    // Parents before children.
    std::sort(missing.begin(), missing.end());
    for (const fs::path& d : missing) {
        std::error_code ec;
        fs::create_directory(d, ec);
        VEIL_CHECK(!ec, "cannot create the reference folder '{}': {}", d.string(), ec.message());
    }
    for (const RegressCase& k : suite.cases)
        if (k.reference == ReferenceKind::File)
            checkOutputPath(k.referenceFile, "reference", {k.scene});
    return missing;
}

nlohmann::json CaseResult::toJson() const {
    nlohmann::json m = nlohmann::json::array();
    for (const MetricResult& r : metrics) {
        nlohmann::json v = {{"name", r.name}, {"threshold", r.threshold}, {"passed", r.passed}};
        // JSON has no NaN or infinity.
        if (std::isfinite(r.value))
            v["value"] = r.value;
        else
            v["value"] = std::isnan(r.value) ? "nan" : (r.value > 0 ? "inf" : "-inf");
        m.push_back(v);
    }
    return {{"name", name},
            {"technique", technique},
            {"reference", reference},
            {"scene", scene},
            {"note", note},
            {"overrides", overrides},
            {"width", width},
            {"height", height},
            {"seeds", seeds},
            {"passed", passed},
            {"error", error},
            {"metrics", m},
            {"seconds", seconds},
            {"heat_scale", heatScale},
            {"render_png", renderPng},
            {"reference_png", referencePng},
            {"diff_png", diffPng}};
}

CaseResult CaseResult::fromJson(const nlohmann::json& j) {
    CaseResult r;
    r.name = j.at("name");
    r.technique = j.at("technique");
    r.reference = j.at("reference");
    r.scene = j.at("scene");
    r.note = j.at("note");
    if (j.contains("overrides")) r.overrides = j.at("overrides").get<std::vector<std::string>>();
    r.width = j.at("width");
    r.height = j.at("height");
    r.seeds = j.at("seeds");
    r.passed = j.at("passed");
    r.error = j.at("error");
    r.seconds = j.at("seconds");
    r.heatScale = j.at("heat_scale");
    r.renderPng = j.at("render_png");
    r.referencePng = j.at("reference_png");
    r.diffPng = j.at("diff_png");
    for (const auto& m : j.at("metrics")) {
        MetricResult x;
        x.name = m.at("name");
        x.threshold = m.at("threshold");
        x.passed = m.at("passed");
        const auto& v = m.at("value");
        if (v.is_number())
            x.value = v.get<double>();
        else {
            const std::string s = v.get<std::string>();
            x.value = s == "inf"    ? std::numeric_limits<double>::infinity()
                      : s == "-inf" ? -std::numeric_limits<double>::infinity()
                                    : std::nan("");
        }
        r.metrics.push_back(x);
    }
    return r;
}

} // namespace veil::regress
