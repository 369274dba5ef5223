// API-sequence fuzzer: a seeded random sequence of the public Module calls, as a host engine might make
// them in any order, on a small module (virtual shadow maps on, targets up to 80x80, two frames in flight
// with host-owned fences, validation layer on). Each step is one call with a valid, edge or broken value
// (NaN, degenerate cones, removed and made-up ids, wrong target formats, a mesh still in use, ...). The
// run fails at the first step where
//   - a call the model knows to be valid is refused, or one it knows to be broken is accepted;
//   - a refusal is not one non-empty line;
//   - the validation layer reports anything (messages are printed as they happen);
//   - the module's light count or frame count disagrees with the host's;
//   - record() submits, waits or builds a pipeline (the module's own counters);
// and a crash names its seed and step too (signal handler). Every failure prints the command line that
// replays it. ctest runs it at 10,000 steps (ApiFuzz*); `api_fuzz --steps N --seed S` runs longer.
#include "api_fuzz_host.h"
#include "api_fuzz_values.h"

#include "engine/manylights_diagnostics.h"
#include "gpu/device.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <list>
#include <map>
#include <set>
#include <string>
#include <unistd.h>

namespace ml::fuzz {
namespace {

const char* kHelp =
    R"(usage: api_fuzz [--steps N] [--seed S] [--frame-every K] [--plant skip-fence-wait] [--verbose]
A seeded random sequence of Module API calls (lights, meshes, instances, cameras, targets, LDR/HDR,
shadow filter, culling, bakes, frames with two in flight) under the validation layer (on by itself;
ML_VALIDATION_SYNC=1 adds synchronization validation). Fails (exit 1) at the first step where a valid call
is refused, a broken one accepted, a refusal is not one line, the layer reports a message, or the
module's counts disagree with the host's; prints the command line that replays it.
  --steps N        calls to make (default 10000)
  --seed S         the sequence (default 1)
  --frame-every K  a frame is recorded every K steps on average (default 12)
  --plant WHAT     skip-fence-wait: once, after 40 frames, record into a slot without waiting for its
                   fence (a host bug the run must catch: the check that the harness can fail)
  --verbose        print every step
Last stdout line: {"steps": ..., "seed": ..., "frames": ..., "accepted": ..., "refused": ...,
"validation_messages": 0, "seconds": ...}
)";

struct Options {
    uint64_t steps = 10000, seed = 1, frameEvery = 12;
    bool plantSkipWait = false, verbose = false;
};

// For the signal handler: the seed and step of a crash (written before each step).
char gCrashLine[256];
volatile sig_atomic_t gStep = 0;
void onCrash(int sig) {
    char buf[320];
    int n =
        std::snprintf(buf, sizeof buf, "%s, crashed at step %d (signal %d)\n", gCrashLine, int(gStep), sig);
    if (n > 0) (void)!write(2, buf, size_t(std::min<int>(n, int(sizeof buf))));
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

struct OpCount {
    uint64_t accepted = 0, refused = 0;
    double ms = 0; // wall time of the steps that made the call, host work included
};

class Fuzzer {
  public:
    Fuzzer(const Options& o, Module& m) : o_(o), r_(o.seed), m_(m), dev_(deviceOf(m)), loop_(m) {}
    ~Fuzzer() {
        loop_.waitAll();
        m_.detachTargets();
        for (auto& g : live_) destroyGBuffer(dev_, g);
        for (auto& g : graveyard_) destroyGBuffer(dev_, g);
    }

    // Runs the steps; an empty string, or the first failure.
    std::string run() {
        for (step_ = 0; step_ < o_.steps; ++step_) {
            gStep = sig_atomic_t(step_);
            const auto start = std::chrono::steady_clock::now();
            const std::string failure = oneStep();
            counts_[last_.substr(0, last_.find(' '))].ms +=
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            if (!failure.empty()) return failure;
            if (validationErrors() != 0)
                return "the validation layer reported " + std::to_string(validationErrors()) +
                       " message(s) (printed above) after " + last_;
            if (m_.lightCount() != lights_.size())
                return "lightCount() " + std::to_string(m_.lightCount()) + ", host holds " +
                       std::to_string(lights_.size()) + " after " + last_;
        }
        return {};
    }
    uint64_t frames() const { return loop_.recorded(); }
    const std::map<std::string, OpCount>& counts() const { return counts_; }

  private:
    enum class Targets { None, Own, Host };

    // Checks one call's result against what the host model expects: `expect` 1 accepted, 0 refused,
    // -1 either (a value whose validity the model does not decide). Returns a failure or "".
    template <class R>
    std::string check(const std::string& op, const R& result, int expect, const std::string& what) {
        last_ = op + " (" + what + ")";
        if (o_.verbose)
            std::fprintf(stderr, "step %llu: %s -> %s\n", (unsigned long long)step_, last_.c_str(),
                         result ? "ok" : result.error().c_str());
        OpCount& c = counts_[op];
        (result ? c.accepted : c.refused)++;
        if (!result) {
            const std::string& e = result.error();
            if (e.empty() || e.find('\n') != std::string::npos)
                return op + " (" + what + "): refusal is not one non-empty line: '" + e + "'";
        }
        if (expect == 1 && !result) return op + " (" + what + "): refused: " + result.error();
        if (expect == 0 && result) return op + " (" + what + "): accepted, must be refused";
        return {};
    }

    // An id that no live object of the kind holds: a removed one, or a made-up one.
    uint32_t deadId(const std::vector<uint32_t>& removed, const std::set<uint32_t>& live) {
        for (int tries = 0; tries < 8; ++tries) {
            const uint32_t id = !removed.empty() && r_.chance(0.6) ? r_.pick(removed)
                                : r_.chance(0.5)                   ? r_.bits()
                                                                   : r_.below(64);
            if (!live.count(id)) return id;
        }
        return 0xffffffffu;
    }
    template <class K, class V> static std::set<uint32_t> keys(const std::map<K, V>& m) {
        std::set<uint32_t> s;
        for (auto& [k, v] : m) s.insert(k);
        return s;
    }

    std::string oneStep() {
        // Most steps are cheap calls; a frame every frameEvery steps on average; load-time work (bakes,
        // new host G-buffers) rarely.
        if (r_.below(uint32_t(o_.frameEvery)) == 0) return frame();
        const uint32_t k = r_.below(1000);
        if (k < 120) return addLight();
        if (k < 220) return setLight();
        if (k < 300) return removeLight();
        if (k < 340) return addMesh();
        if (k < 370) return removeMesh();
        if (k < 430) return addInstance();
        if (k < 470) return removeInstance();
        if (k < 570) return moveInstance();
        if (k < 610) return instanceFlags();
        if (k < 680) return camera();
        if (k < 700) return cameraMatrices();
        if (k < 730) return shadowFilter();
        if (k < 760) return hdrSwitch();
        if (k < 790) return createTargets();
        if (k < 815) return setHostTargets();
        if (k < 830) return detach();
        if (k < 860) return settings();
        if (k < 890) return staticShadow();
        if (k < 895) return bake();
        if (k < 900) return readOutput();
        if (k < 905) return submitFrame();
        if (k < 925) return bindings();
        return frame();
    }

    std::string addLight() {
        if (lights_.size() >= 32) return removeLight();
        const Candidate<LightDesc> c = r_.chance(0.3) ? brokenLight(r_) : randomLight(r_);
        const bool valid = validateLight(c.value).ok();
        if (c.broken && valid) return "validateLight accepts a broken light (" + c.what + ")";
        auto id = m_.addLight(c.value);
        if (auto f = check("addLight", id, valid ? 1 : 0, c.what); !f.empty()) return f;
        if (id) lights_[id.value()] = c.value;
        return {};
    }
    std::string setLight() {
        if (lights_.empty() || r_.chance(0.15)) {
            const uint32_t id = deadId(removedLights_, keys(lights_));
            return check("setLight", m_.setLight(id, randomLight(r_).value), 0, "dead id");
        }
        auto it = std::next(lights_.begin(), r_.below(uint32_t(lights_.size())));
        const Candidate<LightDesc> c = r_.chance(0.25) ? brokenLight(r_) : randomLight(r_);
        const bool valid = validateLight(c.value).ok();
        if (c.broken && valid) return "validateLight accepts a broken light (" + c.what + ")";
        auto r = m_.setLight(it->first, c.value);
        if (r) it->second = c.value;
        return check("setLight", r, valid ? 1 : 0, c.what);
    }
    std::string removeLight() {
        if (lights_.empty() || r_.chance(0.2))
            return check("removeLight", m_.removeLight(deadId(removedLights_, keys(lights_))), 0, "dead id");
        auto it = std::next(lights_.begin(), r_.below(uint32_t(lights_.size())));
        const LightId id = it->first;
        lights_.erase(it);
        removedLights_.push_back(id);
        return check("removeLight", m_.removeLight(id), 1, "live id");
    }

    std::string addMesh() {
        if (meshes_.size() >= 6) return removeMesh();
        const Candidate<Geometry> g = randomGeometry(r_);
        auto id = m_.addMesh({g.value.vertices, g.value.indices, r_.chance(0.5), "fuzz"});
        if (id) meshes_[id.value()] = 0;
        return check("addMesh", id, g.broken ? 0 : 1, g.what);
    }
    std::string removeMesh() {
        if (meshes_.empty() || r_.chance(0.2))
            return check("removeMesh", m_.removeMesh(deadId(removedMeshes_, keys(meshes_))), 0, "dead id");
        auto it = std::next(meshes_.begin(), r_.below(uint32_t(meshes_.size())));
        const MeshId id = it->first;
        const bool used = it->second > 0;
        auto r = m_.removeMesh(id);
        if (!used) meshes_.erase(it), removedMeshes_.push_back(id);
        return check("removeMesh", r, used ? 0 : 1, used ? "in use" : "unused");
    }
    std::string addInstance() {
        if (instances_.size() >= 12) return removeInstance();
        const bool dynamic = r_.chance(0.5);
        const Float3 albedo = r_.chance(0.1) ? Float3(kNaN) : Float3(r_.uniform(0, 1));
        const Candidate<glm::mat4> t = randomInstanceTransform(r_);
        if (meshes_.empty() || r_.chance(0.1)) {
            const MeshId dead = deadId(removedMeshes_, keys(meshes_));
            return check("addInstance", m_.addInstance(dead, t.value, albedo, dynamic), 0, "dead mesh");
        }
        auto mesh = std::next(meshes_.begin(), r_.below(uint32_t(meshes_.size())));
        const bool broken = t.broken || std::isnan(albedo.x);
        auto id = m_.addInstance(mesh->first, t.value, albedo, dynamic);
        if (id) instances_[id.value()] = {mesh->first, dynamic}, mesh->second++;
        return check("addInstance", id, broken ? 0 : 1, std::isnan(albedo.x) ? "NaN albedo" : t.what);
    }
    std::string removeInstance() {
        if (instances_.empty() || r_.chance(0.2))
            return check("removeInstance", m_.removeInstance(deadId(removedInstances_, keys(instances_))), 0,
                         "dead id");
        auto it = std::next(instances_.begin(), r_.below(uint32_t(instances_.size())));
        meshes_[it->second.mesh]--;
        removedInstances_.push_back(it->first);
        auto r = m_.removeInstance(it->first);
        instances_.erase(it);
        return check("removeInstance", r, 1, "live id");
    }
    std::string moveInstance() {
        if (instances_.empty() || r_.chance(0.05))
            return check(
                "setInstanceTransform",
                m_.setInstanceTransform(deadId(removedInstances_, keys(instances_)), glm::mat4(1.0f)), 0,
                "dead id");
        auto it = std::next(instances_.begin(), r_.below(uint32_t(instances_.size())));
        const Candidate<glm::mat4> t = randomInstanceTransform(r_);
        const bool ok = it->second.dynamic && !t.broken;
        return check("setInstanceTransform", m_.setInstanceTransform(it->first, t.value), ok ? 1 : 0,
                     it->second.dynamic ? t.what : "static instance");
    }
    std::string instanceFlags() {
        const bool dead = instances_.empty() || r_.chance(0.1);
        const InstanceId id =
            dead ? deadId(removedInstances_, keys(instances_))
                 : std::next(instances_.begin(), r_.below(uint32_t(instances_.size())))->first;
        switch (r_.below(3)) {
        case 0:
            return check("setInstanceShadowCasting", m_.setInstanceShadowCasting(id, r_.chance(0.5)),
                         dead ? 0 : 1, dead ? "dead id" : "live id");
        case 1:
            return check("setInstanceShadowReceiving", m_.setInstanceShadowReceiving(id, r_.chance(0.5)),
                         dead ? 0 : 1, dead ? "dead id" : "live id");
        default: {
            const bool bad = r_.chance(0.3);
            const float rough = bad ? (r_.chance(0.5) ? kNaN : 1.5f) : r_.uniform(0, 1);
            return check("setInstanceMaterial", m_.setInstanceMaterial(id, rough, r_.uniform(0, 1)),
                         dead || bad ? 0 : 1,
                         dead  ? "dead id"
                         : bad ? "roughness out of [0, 1]"
                               : "valid");
        }
        }
    }

    std::string camera() {
        const Candidate<CameraDesc> c = randomCamera(r_);
        const bool valid = validateCamera(c.value).ok();
        if (c.broken && valid) return "validateCamera accepts a broken camera (" + c.what + ")";
        auto r = m_.setCamera(c.value);
        cameraSet_ = cameraSet_ || r.ok();
        return check("setCamera", r, valid ? 1 : 0, c.what);
    }
    std::string cameraMatrices() {
        const auto c = randomMatrices(r_);
        const Float2 jitter = r_.chance(0.3) ? Float2(r_.uniform(-1, 1), r_.uniform(-1, 1)) : Float2();
        auto r = m_.setCameraMatrices(c.value.first, c.value.second, jitter);
        cameraSet_ = cameraSet_ || r.ok();
        return check("setCameraMatrices", r, c.broken ? 0 : 1, c.what);
    }
    std::string shadowFilter() {
        const uint32_t radius = r_.below(7); // 0..4 valid, 5 and 6 refused
        return check("setShadowFilter", m_.setShadowFilter(radius, r_.chance(0.5)), radius <= 4 ? 1 : 0,
                     "radius " + std::to_string(radius));
    }
    std::string settings() {
        switch (r_.below(6)) {
        case 0:
            last_ = "setCulling";
            m_.setCulling(r_.pick(std::vector<CullingMode>{CullingMode::Clustered, CullingMode::Tiled,
                                                           CullingMode::None, CullingMode::ClusteredBrute}));
            counts_[last_].accepted++;
            return {};
        case 1:
            last_ = "setView", m_.setView(DebugView(r_.below(4))), counts_[last_].accepted++;
            return {};
        case 2:
            last_ = "setStatistics", m_.setStatistics(r_.chance(0.3)), counts_[last_].accepted++;
            return {};
        case 3: {
            const bool bad = r_.chance(0.3);
            return check("setExposure",
                         m_.setExposure(bad ? (r_.chance(0.5) ? kNaN : -1.0f) : r_.uniform(0.1f, 8)),
                         bad ? 0 : 1, bad ? "NaN or negative" : "valid");
        }
        case 4: {
            const bool bad = r_.chance(0.3);
            return check("setExposureEV100", m_.setExposureEV100(bad ? kInf : r_.uniform(-2, 16)),
                         bad ? 0 : 1, bad ? "infinite" : "valid");
        }
        default: {
            const bool bad = r_.chance(0.3);
            const Float3 ambient(bad ? kNaN : r_.uniform(0, 0.2f));
            return check("setEnvironment", m_.setEnvironment(ambient, Float3(r_.uniform(0, 1))), bad ? 0 : 1,
                         bad ? "NaN ambient" : "valid");
        }
        }
    }

    // LDR <-> HDR: the module's own targets hold both outputs; host targets only their output's mode.
    std::string hdrSwitch() {
        const bool hdr = r_.chance(0.5);
        const int expect = targets_ == Targets::Host ? (hdr == hostHdr_ ? 1 : 0) : 1;
        auto r = m_.setHdrOutput(hdr);
        if (r && m_.hdrOutput() != hdr)
            return "setHdrOutput(" + std::to_string(hdr) + ") accepted, hdrOutput() disagrees";
        return check("setHdrOutput", r, expect,
                     targets_ == Targets::Host ? "host targets" : "own or no targets");
    }
    std::string createTargets() {
        const bool zero = r_.chance(0.1);
        const uint32_t w = zero ? 0 : 1 + r_.below(80), h = 1 + r_.below(80);
        auto r = m_.createTargets(w, h, r_.chance(0.5));
        if (auto f = check("createTargets", r, zero ? 0 : 1, std::to_string(w) + "x" + std::to_string(h));
            !f.empty())
            return f;
        if (r)
            targets_ = Targets::Own, ownRecorded_ = false, ownWidth_ = w, ownHeight_ = h, retireHostTargets();
        return {};
    }
    // Host G-buffers: a new one (sometimes with a broken description, refused), or the current one again
    // with the other output mode.
    std::string setHostTargets() {
        if (live_.empty() || r_.chance(0.3)) {
            if (live_.size() >= 3) retireHostTargets(true);
            const uint32_t w = 8 + r_.below(72), h = 8 + r_.below(72);
            live_.push_back(makeGBuffer(dev_, w, h, r_.chance(0.5)));
        }
        auto g = std::prev(live_.end());
        const bool hdr = r_.chance(0.5);
        HostTargets t = g->targets(hdr);
        if (r_.chance(0.7) || hdr != m_.hdrOutput()) t.hdrOutput = hdr;
        std::string what = "valid";
        if (r_.chance(0.3)) {
            switch (r_.below(5)) {
            case 0:
                t.output.format = VK_FORMAT_R8G8B8A8_SRGB, what = "sRGB output";
                break;
            case 1:
                t.depth.format = VK_FORMAT_D16_UNORM, what = "D16 depth";
                break;
            case 2:
                t.albedo.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, what = "albedo not sampled";
                break;
            case 3:
                t.width = g->width + 1 + r_.below(16), what = "wider than the images";
                break;
            default:
                t.normal.view = VK_NULL_HANDLE, what = "no normal view";
                break;
            }
        }
        auto r = m_.setTargets(t);
        if (auto f = check("setTargets", r, what == "valid" ? 1 : 0, what); !f.empty()) return f;
        if (r) {
            targets_ = Targets::Host;
            attached_ = g;
            hostHdr_ = hdr;
            if (m_.hdrOutput() != hdr)
                return std::string("setTargets with an ") + (hdr ? "HDR" : "LDR") +
                       " output left hdrOutput() " + (hdr ? "false" : "true");
            // The G-buffer the module held before may still be read by frames in flight: the graveyard
            // keeps it until the next wait for both.
            retireHostTargets();
        }
        return {};
    }
    std::string detach() {
        m_.detachTargets();
        last_ = "detachTargets";
        counts_["detachTargets"].accepted++;
        targets_ = Targets::None;
        retireHostTargets();
        return {};
    }
    // Every host G-buffer but the attached one goes to the graveyard (all = true: the attached one too,
    // after waiting for the frames in flight and detaching it); the graveyard is destroyed after a wait
    // for both frames in flight.
    void retireHostTargets(bool all = false) {
        if (all) {
            loop_.waitAll();
            m_.detachTargets();
            if (targets_ == Targets::Host) targets_ = Targets::None;
        }
        if (targets_ != Targets::Host) attached_ = live_.end();
        for (auto it = live_.begin(); it != live_.end();) {
            if (it == attached_) {
                ++it;
                continue;
            }
            graveyard_.push_back(*it);
            it = live_.erase(it);
        }
        if (all || graveyard_.size() > 4) {
            loop_.waitAll();
            for (auto& g : graveyard_) destroyGBuffer(dev_, g);
            graveyard_.clear();
        }
    }

    std::string staticShadow() {
        if (lights_.empty()) return {};
        const LightId id = std::next(lights_.begin(), r_.below(uint32_t(lights_.size())))->first;
        if (r_.chance(0.3)) {
            m_.clearStaticShadow(id);
            last_ = "clearStaticShadow";
            counts_[last_].accepted++;
            return {};
        }
        // Random words: the module validates an encoding before any shader reads it; whatever it accepts
        // must render without a validation message.
        std::vector<uint32_t> words(r_.below(64));
        for (uint32_t& w : words) w = r_.chance(0.5) ? r_.bits() : r_.below(16);
        StaticShadowDesc d;
        d.method = StaticMethod(1 + r_.below(5));
        d.frustum.view = glm::lookAt(glm::vec3(0, 5, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, 1));
        d.face = r_.below(8);
        d.words = words;
        return check("setStaticShadow", m_.setStaticShadow(id, d), -1, "random words");
    }
    std::string bake() {
        loop_.waitAll(); // bakeStaticShadows waits for the device itself; the host's frames are done anyway
        const StaticMethod method = r_.pick(std::vector<StaticMethod>{
            StaticMethod::SM, StaticMethod::MH, StaticMethod::DAGMH, StaticMethod::CPVS});
        const bool bad = r_.chance(0.2);
        // CPVS takes powers of two from 64 only: a light's own shadowResolution hint (8..127 here) may
        // not be one, and the bake then refuses that light.
        const bool cpvs = method == StaticMethod::CPVS;
        return check("bakeStaticShadows",
                     m_.bakeStaticShadows(bad ? StaticMethod::None : method, cpvs ? 64 : 16 + r_.below(17)),
                     bad    ? 0
                     : cpvs ? -1
                            : 1,
                     bad    ? "no method"
                     : cpvs ? "cpvs 64"
                            : "16..32");
    }
    std::string readOutput() {
        loop_.waitAll();
        std::vector<uint8_t> rgba;
        auto r = m_.readOutput(rgba);
        // Module-owned LDR targets only, once a frame was recorded into them.
        const bool ok = targets_ == Targets::Own && !m_.hdrOutput() && ownRecorded_;
        if (r && rgba.size() != size_t(ownWidth_) * ownHeight_ * 4)
            return "readOutput gave " + std::to_string(rgba.size()) + " bytes for " +
                   std::to_string(ownWidth_) + "x" + std::to_string(ownHeight_) + " targets";
        return check("readOutput", r, ok ? 1 : 0, ok ? "own LDR targets with a frame" : "not readable");
    }
    std::string submitFrame() {
        loop_.waitAll(); // submitFrame records into the next slot: its frame must be done
        const bool canRecord = targets_ != Targets::None && cameraSet_;
        auto r = m_.submitFrame();
        if (r) loop_.countSubmitFrame(), ownRecorded_ = ownRecorded_ || targets_ == Targets::Own;
        return check("submitFrame", r, targets_ == Targets::Own && cameraSet_ ? 1 : canRecord ? -1 : 0, "");
    }
    std::string bindings() {
        auto b = m_.hostShaderBindings();
        if (auto f = check("hostShaderBindings", b, loop_.recorded() > 0 ? 1 : 0, ""); !f.empty()) return f;
        if (b && b->frame + 1 != loop_.recorded())
            return "hostShaderBindings().frame " + std::to_string(b->frame) + " after " +
                   std::to_string(loop_.recorded()) + " frames";
        return {};
    }

    std::string frame() {
        const bool canRecord = targets_ != Targets::None && cameraSet_;
        const bool skipWait = o_.plantSkipWait && !planted_ && loop_.recorded() >= 40;
        planted_ = planted_ || skipWait;
        auto r = loop_.frame(skipWait);
        if (auto f = check("record", r, canRecord ? 1 : 0,
                           canRecord ? "targets and camera" : "no targets or camera");
            !f.empty())
            return f;
        if (!r) return {};
        ownRecorded_ = ownRecorded_ || targets_ == Targets::Own;
        // record() never submits, waits or builds a pipeline (Timestamps timing): the module's own counts.
        const auto q = diag::queueAccessCounts(m_);
        if (q.recordSubmits || q.recordWaits || q.recordPipelines)
            return "record() made " + std::to_string(q.recordSubmits) + " submits, " +
                   std::to_string(q.recordWaits) + " waits, " + std::to_string(q.recordPipelines) +
                   " pipeline builds";
        const std::string recorded = last_; // the step stays record()'s in the table and in a failure
        const std::string f = bindings();
        last_ = recorded;
        return f;
    }

    struct InstanceState {
        MeshId mesh;
        bool dynamic;
    };
    Options o_;
    Rng r_;
    Module& m_;
    Device& dev_;
    FrameLoop loop_;
    uint64_t step_ = 0;
    std::string last_ = "nothing";
    std::map<std::string, OpCount> counts_;
    std::map<LightId, LightDesc> lights_;
    std::map<MeshId, uint32_t> meshes_; // instances using it
    std::map<InstanceId, InstanceState> instances_;
    std::vector<uint32_t> removedLights_, removedMeshes_, removedInstances_;
    Targets targets_ = Targets::None;
    bool hostHdr_ = false, cameraSet_ = false, planted_ = false;
    bool ownRecorded_ = false; // a frame was recorded into the module's current own targets
    uint32_t ownWidth_ = 0, ownHeight_ = 0;
    std::list<HostGBuffer> live_; // host G-buffers not destroyed
    std::list<HostGBuffer>::iterator attached_ = live_.end();
    std::vector<HostGBuffer> graveyard_;
};

bool parseUint(const char* s, uint64_t& out) {
    char* end = nullptr;
    out = std::strtoull(s, &end, 10);
    return s[0] >= '0' && s[0] <= '9' && end && *end == 0;
}

} // namespace
} // namespace ml::fuzz

int main(int argc, char** argv) {
    using namespace ml::fuzz;
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") return std::fputs(kHelp, stdout), 0;
        if (a == "--verbose") {
            o.verbose = true;
            continue;
        }
        uint64_t* target = a == "--steps"         ? &o.steps
                           : a == "--seed"        ? &o.seed
                           : a == "--frame-every" ? &o.frameEvery
                                                  : nullptr;
        if (a == "--plant" && i + 1 < argc && std::string(argv[i + 1]) == "skip-fence-wait") {
            o.plantSkipWait = true, ++i;
            continue;
        }
        if (!target || i + 1 >= argc || !parseUint(argv[++i], *target) ||
            (target == &o.frameEvery && *target == 0)) {
            std::fprintf(stderr, "api_fuzz: bad argument '%s' (--help)\n", a.c_str());
            return 2;
        }
    }
    std::snprintf(gCrashLine, sizeof gCrashLine, "api_fuzz: seed %llu", (unsigned long long)o.seed);
    for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGILL, SIGBUS}) std::signal(sig, onCrash);
    const auto start = std::chrono::steady_clock::now();

    ml::resetValidationCounters();
    ml::ModuleOptions mo;
    mo.device.validation = true;
    mo.timing = ml::TimingChoice::Timestamps; // frames recorded into the host's command buffers
    mo.framesInFlight = 2;
    mo.vsm.enabled = true;
    mo.vsm.resolution = 1024;
    mo.vsm.poolPages = 128;
    mo.vsm.initialMaps = 1; // the slot pool grows while the run adds shadowed lights
    mo.vsm.maxMaps = 32;
    auto made = ml::Module::create(mo);
    if (!made) return std::fprintf(stderr, "api_fuzz: Module::create: %s\n", made.error().c_str()), 1;
    std::string failure;
    uint64_t frames = 0;
    std::map<std::string, OpCount> counts;
    {
        Fuzzer f(o, *made.value());
        failure = f.run();
        frames = f.frames();
        counts = f.counts();
    }
    made.value().reset();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    uint64_t accepted = 0, refused = 0;
    std::printf("| call | accepted | refused | ms |\n|---|---:|---:|---:|\n");
    for (auto& [op, c] : counts) {
        std::printf("| %s | %llu | %llu | %.0f |\n", op.c_str(), (unsigned long long)c.accepted,
                    (unsigned long long)c.refused, c.ms);
        accepted += c.accepted, refused += c.refused;
    }
    if (failure.empty() && ml::validationErrors() != 0)
        failure = "the validation layer reported a message (printed above) at teardown";
    if (!failure.empty()) {
        std::fprintf(stderr,
                     "api_fuzz: seed %llu step %llu: %s\nreplay: api_fuzz --seed %llu --steps %llu "
                     "--frame-every %llu --verbose\n",
                     (unsigned long long)o.seed, (unsigned long long)gStep, failure.c_str(),
                     (unsigned long long)o.seed, (unsigned long long)gStep + 1,
                     (unsigned long long)o.frameEvery);
        return 1;
    }
    std::printf("{\"steps\": %llu, \"seed\": %llu, \"frames\": %llu, \"accepted\": %llu, \"refused\": %llu, "
                "\"validation_messages\": %u, \"seconds\": %.1f}\n",
                (unsigned long long)o.steps, (unsigned long long)o.seed, (unsigned long long)frames,
                (unsigned long long)accepted, (unsigned long long)refused, ml::validationErrors(), seconds);
    return 0;
}
