// The module's targets and output mode (manylights/module.h: createTargets, setTargets, setHdrOutput):
// the host targets' checks, the module-owned images, and the deferred release of images and buffers
// that frames in flight may still use, so that none of these calls waits for the device.
#include "engine/limits.h"
#include "engine/module_impl.h"

#include <string>

namespace ml {

namespace {

const char* formatName(VkFormat f) {
    switch (f) {
    case VK_FORMAT_D32_SFLOAT:
        return "D32_SFLOAT";
    case VK_FORMAT_D16_UNORM:
        return "D16_UNORM";
    case VK_FORMAT_D24_UNORM_S8_UINT:
        return "D24_UNORM_S8_UINT";
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
        return "D32_SFLOAT_S8_UINT";
    case VK_FORMAT_R16G16B16A16_SFLOAT:
        return "R16G16B16A16_SFLOAT";
    case VK_FORMAT_R8G8B8A8_UNORM:
        return "R8G8B8A8_UNORM";
    case VK_FORMAT_R8G8_UNORM:
        return "R8G8_UNORM";
    case VK_FORMAT_R16G16_UNORM:
        return "R16G16_UNORM";
    case VK_FORMAT_R8G8B8A8_SRGB:
        return "R8G8B8A8_SRGB";
    case VK_FORMAT_B8G8R8A8_UNORM:
        return "B8G8R8A8_UNORM";
    case VK_FORMAT_B8G8R8A8_SRGB:
        return "B8G8R8A8_SRGB";
    case VK_FORMAT_R32G32B32A32_SFLOAT:
        return "R32G32B32A32_SFLOAT";
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32:
        return "A2B10G10R10_UNORM_PACK32";
    case VK_FORMAT_UNDEFINED:
        return "UNDEFINED";
    default:
        return nullptr;
    }
}

std::string formatString(VkFormat f) {
    const char* n = formatName(f);
    return n ? n : "format " + std::to_string(int(f));
}

// One target against its row of HostTargets' table: a one-line reason, or empty.
std::string checkTarget(const char* name, const HostImage& t, VkFormat format, VkImageUsageFlags usage,
                        const char* usageName, uint32_t width, uint32_t height, const char* formatWhy) {
    const std::string what = std::string("setTargets: ") + name + ": ";
    if (!t.image || !t.view) return what + "the image and its view are both required";
    if (t.format != format)
        return what + "format " + formatString(t.format) + ", want " + formatString(format) + formatWhy;
    if ((t.usage & usage) != usage)
        return what + "usage lacks " + usageName + " (the module reads it " +
               (usage == VK_IMAGE_USAGE_STORAGE_BIT ? "as a storage image)" : "by sampling)");
    if (t.extent.width < width || t.extent.height < height)
        return what + "the image is " + std::to_string(t.extent.width) + "x" +
               std::to_string(t.extent.height) + ", smaller than the claimed " + std::to_string(width) + "x" +
               std::to_string(height);
    return {};
}

} // namespace

Result<void> checkHostTargets(const HostTargets& t, bool hdr) {
    if (!t.width || !t.height || t.width > 16384 || t.height > 16384)
        return fail("setTargets: size " + std::to_string(t.width) + "x" + std::to_string(t.height) +
                    " is outside 1x1..16384x16384");
    const VkImageUsageFlags sampled = VK_IMAGE_USAGE_SAMPLED_BIT, storage = VK_IMAGE_USAGE_STORAGE_BIT;
    const VkFormat half = VK_FORMAT_R16G16B16A16_SFLOAT, rgba8 = VK_FORMAT_R8G8B8A8_UNORM;
    for (std::string reason :
         {checkTarget("depth", t.depth, VK_FORMAT_D32_SFLOAT, sampled, "SAMPLED", t.width, t.height,
                      " (world positions are rebuilt from depth: D16/D24 put receivers off their surface)"),
          checkTarget("normal", t.normal, half, sampled, "SAMPLED", t.width, t.height,
                      " (signed world-space normals)"),
          checkTarget("albedo", t.albedo, rgba8, sampled, "SAMPLED", t.width, t.height,
                      " (linear albedo; an sRGB view would be decoded twice)"),
          checkTarget("output", t.output, hdr ? half : rgba8, storage, "STORAGE", t.width, t.height,
                      hdr ? " (HDR mode: linear radiance)"
                          : " (LDR mode: tone-mapped sRGB values written by a compute shader; sRGB formats "
                            "have no storage, and RGBA16F wants HDR mode)")})
        if (!reason.empty()) return fail(reason);
    // Optional: absent (no image and no view) means Lambert + Blinn-Phong shading.
    if (t.material.image || t.material.view)
        if (std::string reason = checkTarget("material", t.material, VK_FORMAT_R8G8_UNORM, sampled, "SAMPLED",
                                             t.width, t.height, " (r perceptual roughness, g metalness)");
            !reason.empty())
            return fail(reason);
    return {};
}

uint64_t Module::Impl::waitIdle() {
    device->waitDevice();
    return ++deviceWaits;
}

// Before the first frame nothing can be in flight: released at once.
void Module::Impl::retire(Image& image) {
    if (image.image && frameIndex == 0) destroyImage(*device, image);
    if (image.image) retired.push_back({frameIndex, {}, image});
    image = {};
}

void Module::Impl::retire(Buffer& buffer) {
    // A copy still queued into it (a record() that failed after staging) is dropped with it.
    std::erase_if(stagedCopies, [&](const StagedCopy& c) { return c.destination == buffer.buffer; });
    if (buffer.buffer && frameIndex == 0) destroyBuffer(*device, buffer);
    if (buffer.buffer) retired.push_back({frameIndex, buffer, {}});
    buffer = {};
}

// At record() of frame F the host has waited for frame F - slots (the framesInFlight contract) and so,
// queue submissions completing in order, for every frame before it. What was retired when frameIndex
// was R was last used by frame R - 1 at the latest: free once F - slots >= R - 1.
void Module::Impl::releaseRetired(bool all) {
    const Device& d = *device;
    size_t kept = 0;
    for (Retired& r : retired) {
        if (all || frameIndex + 1 >= r.frame + slots.size()) {
            destroyBuffer(d, r.buffer);
            destroyImage(d, r.image);
        } else {
            retired[kept++] = std::move(r);
        }
    }
    retired.resize(kept);
}

void Module::Impl::destroyTargets() {
    for (Image* i : {&targets.depth, &targets.normal, &targets.albedo, &targets.material, &hdr, &output})
        retire(*i);
}

// Module-owned targets: full-size HDR and output images, both kept so that the mode switches freely.
// Host targets: the host's output takes what the mode writes, and the evaluation's other storage binding
// gets a 1x1 stub (never written; transitioned each frame like the others, so its layout is valid).
Result<void> Module::Impl::createOutput(bool own) {
    const uint32_t w = own ? width : 1, h = own ? height : 1;
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    ML_TRY(createImage(*device, hdr, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, usage, own ? "hdr" : "hdr_stub"));
    ML_TRY(
        createImage(*device, output, w, h, VK_FORMAT_R8G8B8A8_UNORM, usage, own ? "output" : "output_stub"));
    return {};
}

Result<void> Module::createTargets(uint32_t width, uint32_t height, bool materials) {
    if (width == 0 || height == 0 || width > 16384 || height > 16384)
        return fail("size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is outside 1x1..16384x16384");
    auto& m = *impl_;
    if (auto r = checkTargetLimits(deviceLimitTable(*m.device), width, height, true); !r) return r;
    m.destroyTargets(); // released once the frames in flight that use them are done
    m.ownTargets = true;
    m.targetsDetached = false;
    m.ownOutputRecorded = false;
    m.ownMaterials = materials;
    m.width = width;
    m.height = height;
    auto r = m.gbuffer.createTargets(*m.device, width, height, m.targets);
    if (r) r = m.createOutput(true);
    if (r) r = m.preparePipelines(); // LDR and HDR: record() builds none
    if (!r) { // out of memory: no targets (record() refuses until a later call succeeds)
        m.destroyTargets();
        m.width = m.height = 0;
        return fail("createTargets: " + r.error());
    }
    return {};
}

Result<void> Module::setTargets(const HostTargets& t) {
    auto& m = *impl_;
    const bool hdr = t.hdrOutput.value_or(m.hdrOutput);
    if (auto r = checkHostTargets(t, hdr); !r) return r;
    if (auto r = checkTargetLimits(deviceLimitTable(*m.device), t.width, t.height, false); !r)
        return fail("setTargets: " + r.error());
    m.destroyTargets();
    m.ownTargets = false;
    m.targetsDetached = false;
    m.width = t.width;
    m.height = t.height;
    m.host = t;
    m.hdrOutput = hdr;
    auto r = m.createOutput(false);
    if (r) r = m.preparePipelines(); // the output's mode: record() builds none
    if (!r) {
        m.destroyTargets();
        m.width = m.height = 0;
        return fail("setTargets: " + r.error());
    }
    return {};
}

void Module::detachTargets() {
    auto& m = *impl_;
    if (!m.width) return;
    m.destroyTargets(); // retired: destroyed once the frames in flight that use them are done
    m.host = {};        // no handle of the host's is kept, so none can be written into a descriptor
    m.ownTargets = false;
    m.width = m.height = 0;
    m.targetsDetached = true;
}

Result<void> Module::setHdrOutput(bool hdr) {
    auto& m = *impl_;
    if (m.width && !m.ownTargets && hdr != m.hdrOutput) {
        const VkFormat want = hdr ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R8G8B8A8_UNORM;
        if (m.host.output.format != want)
            return fail(std::string("setHdrOutput: the host's output is ") +
                        formatString(m.host.output.format) + ", " + (hdr ? "HDR" : "LDR") + " wants " +
                        formatString(want) +
                        ": call setTargets with such an output and HostTargets::hdrOutput = " +
                        (hdr ? "true" : "false"));
    }
    m.hdrOutput = hdr;
    return {};
}

bool Module::hdrOutput() const {
    return impl_->hdrOutput;
}

VkImage Module::outputImage() const {
    if (!impl_->ownTargets) return VK_NULL_HANDLE; // the host's own
    return impl_->hdrOutput ? impl_->hdr.image : impl_->output.image;
}

} // namespace ml
