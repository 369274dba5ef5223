#include "bake/reference/raytrace.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

namespace ml {

// Embree reports errors through a callback, possibly from its own build threads; keep the first message
// (later ones are usually consequences of it).
struct RayReference::ErrorSink {
    std::atomic<bool> set{false};
    std::string message;
    static void callback(void* user, RTCError code, const char* text) {
        auto* sink = static_cast<ErrorSink*>(user);
        bool expected = false;
        if (!sink->set.compare_exchange_strong(expected, true)) return;
        sink->message = std::string(errorName(code)) + (text && *text ? std::string(": ") + text : "");
    }
    static const char* errorName(RTCError code) {
        switch (code) {
        case RTC_ERROR_NONE:
            return "no error";
        case RTC_ERROR_UNKNOWN:
            return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_CANCELLED:
            return "cancelled";
        }
        return "unrecognised error";
    }
};

namespace {

// One occlusion segment. Shared by visible() and visibleBatch() so that both trace bit-identical rays for
// the same input.
struct Segment {
    glm::vec3 org, dir;
    float tnear, tfar;
    bool empty; // nothing left to test after the bias cuts: report visible without tracing
};

Segment alongRay(glm::vec3 receiver, glm::vec3 lightPos, float bias) {
    glm::vec3 d = lightPos - receiver;
    float dist = glm::length(d);
    Segment s{receiver, glm::vec3(0.0f, 1.0f, 0.0f), bias, dist - bias, false};
    // Also catches non-finite input: a NaN distance fails the comparison and the ray is not traced.
    if (!(dist > 2.0f * bias) || !(dist > 0.0f)) {
        s.empty = true;
        return s;
    }
    s.dir = d / dist;
    return s;
}

Segment alongNormal(glm::vec3 receiver, glm::vec3 normal, glm::vec3 lightPos, float bias) {
    float len = glm::length(normal);
    if (!(len > 0.0f)) return alongRay(receiver, lightPos, bias);
    glm::vec3 n = normal / len;
    if (glm::dot(n, lightPos - receiver) < 0.0f) n = -n;
    glm::vec3 org = receiver + n * bias;
    glm::vec3 d = lightPos - org;
    float dist = glm::length(d);
    Segment s{org, glm::vec3(0.0f, 1.0f, 0.0f), 0.0f, dist - bias, false};
    if (!(dist > bias)) {
        s.empty = true;
        return s;
    }
    s.dir = d / dist;
    return s;
}

void setRay(RTCRay& r, const Segment& s) {
    r.org_x = s.org.x;
    r.org_y = s.org.y;
    r.org_z = s.org.z;
    r.tnear = s.tnear;
    r.dir_x = s.dir.x;
    r.dir_y = s.dir.y;
    r.dir_z = s.dir.z;
    r.time = 0.0f;
    r.tfar = s.tfar;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
}

template <int N> struct Packet;
template <> struct Packet<4> {
    using Ray = RTCRay4;
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded4(v, s, c, r);
    }
};
template <> struct Packet<8> {
    using Ray = RTCRay8;
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded8(v, s, c, r);
    }
};
template <> struct Packet<16> {
    using Ray = RTCRay16;
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded16(v, s, c, r);
    }
};

bool finiteMatrix(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

} // namespace

Result<RayReference> RayReference::build(const Scene& scene, bool staticOnly) {
    return build(scene, staticOnly, std::string());
}

Result<RayReference> RayReference::build(const Scene& scene, bool staticOnly,
                                         const std::string& deviceConfig) {
    RayReference ref;
    ref.errors_ = std::make_unique<ErrorSink>();
    ErrorSink& sink = *ref.errors_;
    auto embreeError = [&](const char* what) {
        return fail("ray reference: " + std::string(what) +
                    " failed: " + (sink.set ? sink.message : std::string("no message from Embree")));
    };

    ref.device_ = rtcNewDevice(deviceConfig.empty() ? nullptr : deviceConfig.c_str());
    if (!ref.device_) {
        // No device means no callback yet; the global error code is all there is.
        return fail("ray reference: Embree device creation failed (config \"" + deviceConfig +
                    "\"): " + ErrorSink::errorName(rtcGetDeviceError(nullptr)));
    }
    rtcSetDeviceErrorFunction(ref.device_, &ErrorSink::callback, &sink);

    ref.scene_ = rtcNewScene(ref.device_);
    if (!ref.scene_ || sink.set) return embreeError("scene creation");
    // Robust: watertight traversal, no rays slipping between triangles sharing an edge. High quality: the
    // scene is built once and then traced millions of times per measurement.
    rtcSetSceneFlags(ref.scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(ref.scene_, RTC_BUILD_QUALITY_HIGH);

    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        if (staticOnly && inst.dynamic) continue;
        std::string where = "ray reference: instance " + std::to_string(i);
        if (inst.mesh >= scene.meshes.size())
            return fail(where + " names mesh " + std::to_string(inst.mesh) + " but the scene has " +
                        std::to_string(scene.meshes.size()));
        const Mesh& mesh = scene.meshes[inst.mesh];
        where += " (mesh '" + mesh.name + "')";
        if (mesh.indices.size() % 3 != 0)
            return fail(where + ": " + std::to_string(mesh.indices.size()) +
                        " indices is not a whole number of triangles");
        for (uint32_t index : mesh.indices)
            if (index >= mesh.vertices.size())
                return fail(where + ": index " + std::to_string(index) + " out of range (" +
                            std::to_string(mesh.vertices.size()) + " vertices)");
        if (!finiteMatrix(inst.transform)) return fail(where + ": non-finite transform");
        size_t triangles = mesh.indices.size() / 3;
        if (triangles == 0) continue;

        RTCGeometry geom = rtcNewGeometry(ref.device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (!geom) return embreeError("geometry creation");
        // Embree pads this buffer itself (its SSE loads read past the last vertex).
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
        auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles));
        if (!vb || !ib) {
            rtcReleaseGeometry(geom);
            return embreeError("geometry buffer allocation");
        }
        // Transform in double: world coordinates of a city reach hundreds of metres, and float rounding of
        // the product would move shared vertices of neighbouring instances apart by different amounts.
        glm::dmat4 m(inst.transform);
        for (size_t v = 0; v < mesh.vertices.size(); ++v) {
            glm::dvec4 p = m * glm::dvec4(glm::dvec3(mesh.vertices[v].position), 1.0);
            if (p.w != 1.0 && p.w != 0.0) p /= p.w;
            vb[3 * v + 0] = float(p.x);
            vb[3 * v + 1] = float(p.y);
            vb[3 * v + 2] = float(p.z);
        }
        std::copy(mesh.indices.begin(), mesh.indices.end(), ib);
        rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(ref.scene_, geom, unsigned(i));
        if (ref.closed_.size() <= i) ref.closed_.resize(i + 1, 0);
        ref.closed_[i] = mesh.closed ? 1 : 0;
        rtcReleaseGeometry(geom); // the scene holds its own reference
        if (sink.set) return embreeError(("adding instance " + std::to_string(i)).c_str());
        ref.triangles_ += triangles;
        ++ref.geometries_;
    }

    rtcCommitScene(ref.scene_);
    if (sink.set) return embreeError("scene build");

    // rtcOccluded16 on a CPU without 16-wide support is emulated and slower than the native width.
    if (rtcGetDeviceProperty(ref.device_, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED))
        ref.packetWidth_ = 16;
    else if (rtcGetDeviceProperty(ref.device_, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED))
        ref.packetWidth_ = 8;
    else if (rtcGetDeviceProperty(ref.device_, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED))
        ref.packetWidth_ = 4;
    else
        ref.packetWidth_ = 1;
    sink.set = false; // property queries of unsupported features may report; they are not build failures

    unsigned hw = std::thread::hardware_concurrency();
    ref.threads_ = std::clamp(hw, 1u, 2u);
    return ref;
}

RayReference::RayReference(RayReference&& o) noexcept
    : errors_(std::move(o.errors_)), closed_(std::move(o.closed_)), device_(o.device_), scene_(o.scene_),
      triangles_(o.triangles_), geometries_(o.geometries_), threads_(o.threads_),
      packetWidth_(o.packetWidth_) {
    o.device_ = nullptr;
    o.scene_ = nullptr;
}

RayReference& RayReference::operator=(RayReference&& o) noexcept {
    if (this != &o) {
        release();
        errors_ = std::move(o.errors_);
        closed_ = std::move(o.closed_);
        device_ = o.device_;
        scene_ = o.scene_;
        triangles_ = o.triangles_;
        geometries_ = o.geometries_;
        threads_ = o.threads_;
        packetWidth_ = o.packetWidth_;
        o.device_ = nullptr;
        o.scene_ = nullptr;
    }
    return *this;
}

RayReference::~RayReference() {
    release();
}

RayHit RayReference::firstHit(glm::vec3 origin, glm::vec3 dir, float tnear, float tfar) const {
    RayHit out;
    if (!scene_ || !(tfar > tnear)) return out;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    setRay(rh.ray, Segment{origin, dir, tnear, tfar, false});
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
    out.hit = true;
    out.t = rh.ray.tfar;
    out.instance = rh.hit.geomID;
    out.ng = glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    out.closed = rh.hit.geomID < closed_.size() && closed_[rh.hit.geomID];
    return out;
}

void RayReference::release() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
    scene_ = nullptr;
    device_ = nullptr;
}

bool RayReference::visible(glm::vec3 receiver, glm::vec3 lightPos, float bias) const {
    Segment s = alongRay(receiver, lightPos, bias);
    if (s.empty || !scene_) return true;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray;
    setRay(ray, s);
    rtcOccluded1(scene_, &ctx, &ray);
    // Embree sets tfar to -inf on a hit.
    return ray.tfar >= 0.0f;
}

template <int N>
void RayReference::traceRange(const glm::vec3* receivers, const glm::vec3* normals, size_t begin, size_t end,
                              glm::vec3 lightPos, float bias, uint8_t* out) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    // Left at the default (incoherent) flag: measured on fzk-haus, the coherent flag gained nothing for
    // receivers in surface order and lost about a third for receivers in random order.
    alignas(64) typename Packet<N>::Ray rays;
    alignas(64) int valid[N];
    for (size_t base = begin; base < end; base += N) {
        int lanes = int(std::min<size_t>(N, end - base));
        int active = 0;
        for (int k = 0; k < N; ++k) {
            Segment s{};
            s.empty = true;
            if (k < lanes) {
                size_t i = base + k;
                s = normals ? alongNormal(receivers[i], normals[i], lightPos, bias)
                            : alongRay(receivers[i], lightPos, bias);
                if (s.empty) out[i] = 1;
            }
            valid[k] = s.empty ? 0 : -1;
            active += !s.empty;
            rays.org_x[k] = s.org.x;
            rays.org_y[k] = s.org.y;
            rays.org_z[k] = s.org.z;
            rays.tnear[k] = s.tnear;
            rays.dir_x[k] = s.dir.x;
            rays.dir_y[k] = s.dir.y;
            rays.dir_z[k] = s.dir.z;
            rays.time[k] = 0.0f;
            rays.tfar[k] = s.tfar;
            rays.mask[k] = 0xFFFFFFFFu;
            rays.id[k] = unsigned(k);
            rays.flags[k] = 0;
        }
        if (!active) continue;
        Packet<N>::occluded(valid, scene_, &ctx, &rays);
        for (int k = 0; k < lanes; ++k)
            if (valid[k]) out[base + k] = rays.tfar[k] >= 0.0f ? 1 : 0;
    }
}

void RayReference::traceRangeAny(const glm::vec3* receivers, const glm::vec3* normals, size_t begin,
                                 size_t end, glm::vec3 lightPos, float bias, uint8_t* out) const {
    switch (packetWidth_) {
    case 16:
        traceRange<16>(receivers, normals, begin, end, lightPos, bias, out);
        return;
    case 8:
        traceRange<8>(receivers, normals, begin, end, lightPos, bias, out);
        return;
    case 4:
        traceRange<4>(receivers, normals, begin, end, lightPos, bias, out);
        return;
    default:
        break;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = begin; i < end; ++i) {
        Segment s = normals ? alongNormal(receivers[i], normals[i], lightPos, bias)
                            : alongRay(receivers[i], lightPos, bias);
        if (s.empty) {
            out[i] = 1;
            continue;
        }
        RTCRay ray;
        setRay(ray, s);
        rtcOccluded1(scene_, &ctx, &ray);
        out[i] = ray.tfar >= 0.0f ? 1 : 0;
    }
}

void RayReference::visibleBatch(const glm::vec3* receivers, const glm::vec3* normals, size_t n,
                                glm::vec3 lightPos, float bias, uint8_t* out) const {
    if (n == 0) return;
    if (!scene_) {
        std::fill(out, out + n, uint8_t(1));
        return;
    }
    // Work is handed out in chunks: rays towards the light from different parts of the frame cost very
    // different amounts, so a static split would leave one thread idle. Batches under kParallelMin rays
    // (one light's cone in a small frame, a few milliseconds of work) stay on the calling thread: on a
    // shared, busy machine waiting for a second thread to be scheduled costs more than it saves.
    constexpr size_t kChunk = 4096, kParallelMin = 32768;
    unsigned threads =
        n < kParallelMin ? 1u : unsigned(std::min<size_t>(threads_, (n + kChunk - 1) / kChunk));
    if (threads <= 1) {
        traceRangeAny(receivers, normals, 0, n, lightPos, bias, out);
        return;
    }
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (;;) {
            size_t begin = next.fetch_add(kChunk);
            if (begin >= n) return;
            traceRangeAny(receivers, normals, begin, std::min(n, begin + kChunk), lightPos, bias, out);
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
}

void Disagreement::merge(const Disagreement& o) {
    uint64_t total = compared + o.compared;
    if (total)
        meanAbsDiff = (meanAbsDiff * double(compared) + o.meanAbsDiff * double(o.compared)) / double(total);
    compared = total;
    mismatches += o.mismatches;
}

namespace {
Disagreement compare(const std::vector<float>& method, const std::vector<uint8_t>& truth,
                     const std::vector<uint8_t>* include) {
    Disagreement d;
    size_t n = std::min(method.size(), truth.size());
    if (include) n = std::min(n, include->size());
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        if (include && !(*include)[i]) continue;
        float m = method[i];
        bool lit = truth[i] != 0;
        ++d.compared;
        if (std::isnan(m)) {
            ++d.mismatches;
            sum += 1.0;
            continue;
        }
        m = std::clamp(m, 0.0f, 1.0f);
        if ((m >= 0.5f) != lit) ++d.mismatches;
        sum += std::abs(double(m) - (lit ? 1.0 : 0.0));
    }
    d.meanAbsDiff = d.compared ? sum / double(d.compared) : 0.0;
    return d;
}
} // namespace

Disagreement compareVisibility(const std::vector<float>& methodVisibility,
                               const std::vector<uint8_t>& truth) {
    return compare(methodVisibility, truth, nullptr);
}

Disagreement compareVisibility(const std::vector<float>& methodVisibility, const std::vector<uint8_t>& truth,
                               const std::vector<uint8_t>& include) {
    return compare(methodVisibility, truth, &include);
}

bool inLightCone(const Light& light, glm::vec3 p) {
    if (light.type == LightKind::Directional) return true;
    glm::vec3 d = p - light.position;
    float dist = glm::length(d);
    if (!(dist < light.range)) return false;
    if (light.type == LightKind::Point) return true;
    float dirLen = glm::length(light.direction);
    if (!(dist > 0.0f) || !(dirLen > 0.0f)) return false;
    // cos is decreasing on [0, pi], so this is "angle <= outerAngle".
    if (light.outerAngle >= 3.14159265f) return true;
    float c = glm::dot(d / dist, light.direction / dirLen);
    return c >= std::cos(light.outerAngle);
}

} // namespace ml
