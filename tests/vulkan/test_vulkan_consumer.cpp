// A Vulkan engine's use of `leanfade shaders --lang spirv` (docs/integration.md, "Vulkan"): on
// Mesa's lavapipe with the Khronos validation layer, the exported vertex and fragment modules of
// a few variants (Blinn-Phong and Cook-Torrance) draw the sphere with a map from `leanfade bake`
// (every MIP level uploaded), the pipeline layout and the vertex input state made from
// shaders.json's reflection alone, the uniform blocks filled from their C++ mirrors after
// checking the reflected offsets against them. The image is compared with `leanfade render`'s
// cell of the same view (8-bit sRGB codes) and the validation layer must have said nothing.
#include <dlfcn.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/eval/metrics.hpp"
#include "leanfade/gl/detail/figure.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/gl/detail/shading_block.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "leanfade/scene/detail/vertex_layout.hpp"
#include "leanfade/test/cell_comparison.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kSize = 128;  // pixels of a cell, both sides

// The messages of the validation layer (and the loader), every severity from warnings up.
struct Messages {
    int count = 0;
    std::vector<std::string> texts;
};

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                          VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data,
                                          void* user) {
    auto* messages = static_cast<Messages*>(user);
    ++messages->count;
    if (messages->texts.size() < 20)
        messages->texts.push_back(data->pMessage != nullptr ? data->pMessage : "");
    return VK_FALSE;
}

// A Vulkan create-info structure: zeroed, its type set.
template <typename T>
T vk_info(VkStructureType type) {
    T info{};
    info.sType = type;
    return info;
}

#define VK_CHECK(call)                                                     \
    do {                                                                   \
        const VkResult vk_result_ = (call);                                \
        ASSERT_EQ(vk_result_, VK_SUCCESS) << #call << " = " << vk_result_; \
    } while (0)

// Lavapipe's ICD file of this machine (mesa-vulkan-drivers): the loader is pointed at it alone.
fs::path lavapipe_icd() {
    for (const char* folder : {"/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"}) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(folder, ec))
            if (entry.path().filename().string().rfind("lvp_icd", 0) == 0) return entry.path();
    }
    return {};
}

#if defined(__SANITIZE_ADDRESS__)
// `make sanitize`: LeakSanitizer leaves out the blocks that Mesa's lavapipe driver loses itself
// (docs/robustness.md, "Sanitizers"). One draw of the Cook-Torrance variant (scene_lean_plain_ct)
// makes Mesa 22.3.6's lavapipe lose 1,191,240 bytes in 694 allocations in its shader compilation
// (LLVM's JIT registers EH frames for them) after every object this program created was destroyed,
// as the validation layer's object tracker confirms (0 messages at vkDestroyDevice; the other
// variants lose nothing). A block that leanfade or this program allocates has no lavapipe frame
// and is still reported.
extern "C" const char* __lsan_default_suppressions() { return "leak:libvulkan_lvp.so\n"; }
#endif

// Points the loader at lavapipe alone (a machine may have other ICDs installed) and keeps
// lavapipe and the validation layer loaded until the process ends (RTLD_NODELETE). Both keep
// global state for the life of the process (LLVM's among it); unloaded at vkDestroyInstance, their
// data is no longer scanned by LeakSanitizer, which then reports the heap blocks that state still
// holds as leaks from an unknown module (`make sanitize`). With the two libraries loaded for good
// (or preloaded), the same runs report none, and a block our code leaks is still reported.
void use_lavapipe() {
    const fs::path icd = lavapipe_icd();
    if (icd.empty()) return;
    setenv("VK_ICD_FILENAMES", icd.c_str(), 1);
    setenv("VK_DRIVER_FILES", icd.c_str(), 1);
    const fs::path layer = "/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json";
    for (const auto& [manifest, key] : {std::pair{icd, "ICD"}, std::pair{layer, "layer"}}) {
        std::error_code ec;
        if (!fs::is_regular_file(manifest, ec)) continue;
        const nlohmann::json j = nlohmann::json::parse(read_text(manifest), nullptr, false);
        if (!j.is_object() || !j.contains(key) || !j[key].contains("library_path")) continue;
        const std::string library = j[key]["library_path"].get<std::string>();
        ::dlopen(library.c_str(), RTLD_NOW | RTLD_NODELETE);  // a failure: the loader reports it
    }
}

std::vector<std::uint32_t> read_words(const fs::path& file) {
    const std::string bytes = read_text(file);
    std::vector<std::uint32_t> words(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), words.size() * 4);
    return words;
}

VkFormat vk_format(const std::string& name) {
    static const std::map<std::string, VkFormat> formats{
        {"R32_SFLOAT", VK_FORMAT_R32_SFLOAT},
        {"R32G32_SFLOAT", VK_FORMAT_R32G32_SFLOAT},
        {"R32G32B32_SFLOAT", VK_FORMAT_R32G32B32_SFLOAT},
        {"R32G32B32A32_SFLOAT", VK_FORMAT_R32G32B32A32_SFLOAT}};
    const auto it = formats.find(name);
    return it == formats.end() ? VK_FORMAT_UNDEFINED : it->second;
}

VkFormat lean_format(Storage storage) {
    switch (storage) {
        case Storage::Unorm8:
            return VK_FORMAT_R8G8B8A8_UNORM;
        case Storage::Unorm16:
            return VK_FORMAT_R16G16B16A16_UNORM;
        case Storage::Float16:
            return VK_FORMAT_R16G16B16A16_SFLOAT;
        case Storage::Float32:
            return VK_FORMAT_R32G32B32A32_SFLOAT;
    }
    return VK_FORMAT_UNDEFINED;
}

// The variant the renderer draws a colour frame without fog with (gl::variant_for).
std::string renderer_variant(Technique technique, const ShadingSettings& s) {
    gl::RenderRequest request;
    request.technique = technique;
    request.settings = s;
    return gl::variant_name(gl::variant_for(request));
}

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
};

struct Texture {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
};

// One lavapipe device with validation, its queue and a command pool; everything it makes is
// destroyed with it, in reverse order.
class Vulkan {
  public:
    // Messages go to `messages` until the instance is destroyed (its destruction included).
    explicit Vulkan(Messages& messages) : messages(messages) {}
    Vulkan(const Vulkan&) = delete;
    Vulkan& operator=(const Vulkan&) = delete;
    Messages& messages;
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    VkCommandPool pool = VK_NULL_HANDLE;
    std::string device_name;

    ~Vulkan() {
        if (device != VK_NULL_HANDLE) {
            vkDeviceWaitIdle(device);
            for (auto it = cleanup_.rbegin(); it != cleanup_.rend(); ++it) (*it)();
            if (pool != VK_NULL_HANDLE) vkDestroyCommandPool(device, pool, nullptr);
            vkDestroyDevice(device, nullptr);
        }
        if (messenger != VK_NULL_HANDLE) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(instance, messenger, nullptr);
        }
        if (instance != VK_NULL_HANDLE) vkDestroyInstance(instance, nullptr);
    }

    void later(std::function<void()> f) { cleanup_.push_back(std::move(f)); }

    std::uint32_t memory_type(std::uint32_t bits, VkMemoryPropertyFlags wanted) const {
        VkPhysicalDeviceMemoryProperties props;
        vkGetPhysicalDeviceMemoryProperties(physical, &props);
        for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i)
            if ((bits & (1u << i)) != 0 && (props.memoryTypes[i].propertyFlags & wanted) == wanted)
                return i;
        return UINT32_MAX;
    }

  private:
    std::vector<std::function<void()>> cleanup_;
};

void create_vulkan(Vulkan& vk) {
    auto messenger = vk_info<VkDebugUtilsMessengerCreateInfoEXT>(
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
    messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger.pfnUserCallback = on_message;
    messenger.pUserData = &vk.messages;

    std::uint32_t layer_count = 0;
    vkEnumerateInstanceLayerProperties(&layer_count, nullptr);
    std::vector<VkLayerProperties> layers(layer_count);
    vkEnumerateInstanceLayerProperties(&layer_count, layers.data());
    const char* validation = "VK_LAYER_KHRONOS_validation";
    ASSERT_TRUE(std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
        return std::strcmp(l.layerName, validation) == 0;
    })) << "the validation layer is not installed (vulkan-validationlayers)";

    auto app = vk_info<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = "leanfade vulkan consumer";
    app.apiVersion = VK_API_VERSION_1_0;
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    auto info = vk_info<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    info.pNext = &messenger;  // messages of vkCreateInstance and vkDestroyInstance too
    info.pApplicationInfo = &app;
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &validation;
    info.enabledExtensionCount = 1;
    info.ppEnabledExtensionNames = extensions;
    VK_CHECK(vkCreateInstance(&info, nullptr, &vk.instance));
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(vk.instance, "vkCreateDebugUtilsMessengerEXT"));
    ASSERT_NE(create, nullptr);
    VK_CHECK(create(vk.instance, &messenger, nullptr, &vk.messenger));

    std::uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(vk.instance, &count, nullptr));
    ASSERT_GE(count, 1u) << "no Vulkan device: is mesa-vulkan-drivers installed?";
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(vk.instance, &count, devices.data()));
    vk.physical = devices[0];
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(vk.physical, &props);
    vk.device_name = props.deviceName;
    ASSERT_THAT(vk.device_name, testing::HasSubstr("llvmpipe"));

    std::uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(vk.physical, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(vk.physical, &family_count, families.data());
    std::uint32_t family = UINT32_MAX;
    for (std::uint32_t i = 0; i < family_count; ++i)
        if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0) family = i;
    ASSERT_NE(family, UINT32_MAX);
    const float priority = 1.0f;
    auto queue = vk_info<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    queue.queueFamilyIndex = family;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    auto device = vk_info<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    device.queueCreateInfoCount = 1;
    device.pQueueCreateInfos = &queue;
    VK_CHECK(vkCreateDevice(vk.physical, &device, nullptr, &vk.device));
    vkGetDeviceQueue(vk.device, family, 0, &vk.queue);
    auto pool = vk_info<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pool.queueFamilyIndex = family;
    VK_CHECK(vkCreateCommandPool(vk.device, &pool, nullptr, &vk.pool));
}

void create_buffer(Vulkan& vk, VkDeviceSize size, VkBufferUsageFlags usage, Buffer& out) {
    auto info = vk_info<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    info.size = size;
    info.usage = usage;
    VK_CHECK(vkCreateBuffer(vk.device, &info, nullptr, &out.buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(vk.device, out.buffer, &req);
    auto alloc = vk_info<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex =
        vk.memory_type(req.memoryTypeBits,
                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    ASSERT_NE(alloc.memoryTypeIndex, UINT32_MAX);
    VK_CHECK(vkAllocateMemory(vk.device, &alloc, nullptr, &out.memory));
    VK_CHECK(vkBindBufferMemory(vk.device, out.buffer, out.memory, 0));
    VK_CHECK(vkMapMemory(vk.device, out.memory, 0, VK_WHOLE_SIZE, 0, &out.mapped));
    VkDevice device = vk.device;
    const Buffer b = out;
    vk.later([device, b] {
        vkDestroyBuffer(device, b.buffer, nullptr);
        vkFreeMemory(device, b.memory, nullptr);
    });
}

void create_image(Vulkan& vk, VkFormat format, int width, int height, std::uint32_t levels,
                  std::uint32_t layers, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                  VkImageViewType view_type, Texture& out) {
    auto info = vk_info<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {std::uint32_t(width), std::uint32_t(height), 1};
    info.mipLevels = levels;
    info.arrayLayers = layers;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(vk.device, &info, nullptr, &out.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(vk.device, out.image, &req);
    auto alloc = vk_info<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = vk.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    ASSERT_NE(alloc.memoryTypeIndex, UINT32_MAX);
    VK_CHECK(vkAllocateMemory(vk.device, &alloc, nullptr, &out.memory));
    VK_CHECK(vkBindImageMemory(vk.device, out.image, out.memory, 0));
    auto view = vk_info<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
    view.image = out.image;
    view.viewType = view_type;
    view.format = format;
    view.subresourceRange = {aspect, 0, levels, 0, layers};
    VK_CHECK(vkCreateImageView(vk.device, &view, nullptr, &out.view));
    VkDevice device = vk.device;
    const Texture t = out;
    vk.later([device, t] {
        vkDestroyImageView(device, t.view, nullptr);
        vkDestroyImage(device, t.image, nullptr);
        vkFreeMemory(device, t.memory, nullptr);
    });
}

void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
             VkImageLayout to, VkAccessFlags src_access, VkAccessFlags dst_access,
             VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage) {
    auto b = vk_info<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
    b.srcAccessMask = src_access;
    b.dstAccessMask = dst_access;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

// Records `record` into a one-time command buffer, submits it and waits.
template <typename Record>
void submit(Vulkan& vk, const Record& record) {
    auto alloc =
        vk_info<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    alloc.commandPool = vk.pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(vk.device, &alloc, &cmd));
    auto begin = vk_info<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    record(cmd);
    VK_CHECK(vkEndCommandBuffer(cmd));
    auto info = vk_info<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    info.commandBufferCount = 1;
    info.pCommandBuffers = &cmd;
    VK_CHECK(vkQueueSubmit(vk.queue, 1, &info, VK_NULL_HANDLE));
    VK_CHECK(vkQueueWaitIdle(vk.queue));
    vkFreeCommandBuffers(vk.device, vk.pool, 1, &cmd);
}

// Uploads `layers` x `levels` images (each level's layers tightly packed rows, row 0 first as
// given) through a staging buffer and leaves the image ready for sampling.
void upload(Vulkan& vk, const Texture& texture, const std::vector<std::vector<std::uint8_t>>& data,
            const std::vector<VkBufferImageCopy>& regions) {
    std::size_t total = 0;
    for (const auto& d : data) total += d.size();
    Buffer staging;
    ASSERT_NO_FATAL_FAILURE(create_buffer(vk, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, staging));
    std::size_t at = 0;
    for (const auto& d : data) {
        std::memcpy(static_cast<std::uint8_t*>(staging.mapped) + at, d.data(), d.size());
        at += d.size();
    }
    submit(vk, [&](VkCommandBuffer cmd) {
        barrier(cmd, texture.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        vkCmdCopyBufferToImage(cmd, staging.buffer, texture.image,
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, std::uint32_t(regions.size()),
                               regions.data());
        barrier(cmd, texture.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
    });
}

// The rows of an image bottom first (as the renderer uploads them: +v up).
std::vector<std::uint8_t> flip_rows(const std::vector<std::uint8_t>& bytes, int width, int height,
                                    int texel_bytes) {
    const std::size_t row = std::size_t(width) * std::size_t(texel_bytes);
    std::vector<std::uint8_t> out(bytes.size());
    for (int y = 0; y < height; ++y)
        std::memcpy(out.data() + std::size_t(y) * row,
                    bytes.data() + std::size_t(height - 1 - y) * row, row);
    return out;
}

// The modules' descriptors as one set: every binding either stage reads, with the stages that
// read it; two stages that name one binding must agree on its type and count.
struct Binding {
    VkDescriptorSetLayoutBinding layout{};
    std::string name;
    std::uint32_t block_size = 0;
};

void collect_bindings(const json& reflection, std::map<std::uint32_t, Binding>& out) {
    const std::string stage = reflection["stage"];
    const VkShaderStageFlags flag =
        stage == "vertex" ? VK_SHADER_STAGE_VERTEX_BIT : VK_SHADER_STAGE_FRAGMENT_BIT;
    for (const json& r : reflection["resources"]) {
        ASSERT_EQ(r["set"], 0);
        ASSERT_EQ(r["stage"], stage);
        const std::string kind = r["descriptor_type"];
        const VkDescriptorType type = kind == "uniform_buffer"
                                          ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER
                                          : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        ASSERT_TRUE(kind == "uniform_buffer" || kind == "combined_image_sampler") << kind;
        const std::uint32_t binding = r["binding"];
        Binding& b = out[binding];
        if (b.name.empty()) {
            b.name = r["name"];
            b.layout.binding = binding;
            b.layout.descriptorType = type;
            b.layout.descriptorCount = r["array_size"];
            if (kind == "uniform_buffer") b.block_size = r["block_size"];
        } else {
            ASSERT_EQ(b.name, r["name"].get<std::string>());
            ASSERT_EQ(b.layout.descriptorType, type);
        }
        b.layout.stageFlags |= flag;
    }
}

// The reflected members of a block against its C++ mirror's std140 list (names and offsets;
// arrays are listed by their first element there).
void expect_block_matches(const json& resource, const std::vector<gl::BlockMember>& mirror) {
    std::map<std::string, std::size_t> reflected;
    for (const json& m : resource["members"])
        reflected[m["name"].get<std::string>() + (m.contains("array_size") ? "[0]" : "")] =
            m["offset"];
    std::map<std::string, std::size_t> expected;
    for (const gl::BlockMember& m : mirror) expected[m.name] = m.offset;
    EXPECT_EQ(reflected, expected) << resource["name"];
}

struct Frame {
    Image image;
    Messages messages;
};

class VulkanConsumer : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        scratch_ = new fs::path(scratch_folder_for_this_selection("vulkan_consumer"));
        const fs::path& s = *scratch_;
        use_lavapipe();  // the loader sees lavapipe only
        setup_ = new std::string;
        auto run = [&](const std::string& args) {
            const RunResult r = run_leanfade(args, s);
            if (r.exit_code != 0) *setup_ += "leanfade " + args + ": " + r.err;
            return r;
        };
        const RunResult exported = run("shaders --lang spirv -o " + shell_quote(s / "spirv"));
        std::printf("%s", exported.out.c_str());
        run("bake --builtin bumps --size 128 -o " + shell_quote(s / "bumps.ktx2"));
        // The same views drawn by the OpenGL renderer: a cell per technique and distance, its
        // linear radiance as PFM.
        run("render --scene sphere --bumps " + shell_quote(s / "bumps.ktx2") +
            " --techniques bump,lean,fade --distances 3,12 --size " + std::to_string(kSize) + "x" +
            std::to_string(kSize) + " --cells " + shell_quote(s / "cells") +
            " --cell-format pfm -o " + shell_quote(s / "figure.png"));
        // Cook-Torrance, whose variants read the base roughness binding too.
        run("render --scene sphere --bumps " + shell_quote(s / "bumps.ktx2") +
            " --brdf cook-torrance --techniques lean --distances 3 --size " +
            std::to_string(kSize) + "x" + std::to_string(kSize) + " --cells " +
            shell_quote(s / "cells_ct") + " --cell-format pfm -o " +
            shell_quote(s / "figure_ct.png"));
    }
    static void TearDownTestSuite() {
        delete scratch_;
        delete setup_;
    }

    void SetUp() override {
        ASSERT_FALSE(lavapipe_icd().empty())
            << "lavapipe's ICD file is missing (mesa-vulkan-drivers)";
        ASSERT_EQ(*setup_, "");
        index_ = json::parse(read_text(*scratch_ / "spirv" / "shaders.json"));
    }

    const json& entry(const std::string& variant, const std::string& stage) const {
        for (const json& s : index_["shaders"])
            if (s["variant"] == variant && s["stage"] == stage) return s;
        static const json none;
        ADD_FAILURE() << "no " << stage << " stage of " << variant << " in shaders.json";
        return none;
    }

    // Draws the sphere with the exported modules of `variant` as a Vulkan engine would, the
    // blocks filled from `settings` (the defaults: `leanfade render` without flags).
    void draw(const std::string& variant, float distance, VkFrontFace front_face, Frame& frame,
              const ShadingSettings& settings = {});

    static fs::path* scratch_;
    static std::string* setup_;
    json index_;
    std::string device_name_;
};

fs::path* VulkanConsumer::scratch_ = nullptr;
std::string* VulkanConsumer::setup_ = nullptr;

void VulkanConsumer::draw(const std::string& variant, float distance, VkFrontFace front_face,
                          Frame& frame, const ShadingSettings& settings) {
    const json& vert = entry("scene", "vert");
    const json& frag = entry(variant, "frag");
    ASSERT_FALSE(vert.is_null() || frag.is_null());
    const fs::path folder = *scratch_ / "spirv";
    const PackedLeanMap map = io::read_ktx2((*scratch_ / "bumps.ktx2").string());
    ASSERT_GE(map.levels.size(), 8u);  // 128 x 128 down to 1 x 1

    Vulkan vk(frame.messages);
    ASSERT_NO_FATAL_FAILURE(create_vulkan(vk));
    VkDevice device = vk.device;

    // --- Shaders, descriptor set layout and pipeline layout from the reflection.
    std::map<std::uint32_t, Binding> bindings;
    ASSERT_NO_FATAL_FAILURE(collect_bindings(vert["reflection"], bindings));
    ASSERT_NO_FATAL_FAILURE(collect_bindings(frag["reflection"], bindings));
    std::vector<VkDescriptorSetLayoutBinding> layout_bindings;
    for (const auto& [number, b] : bindings) layout_bindings.push_back(b.layout);
    auto set_info = vk_info<VkDescriptorSetLayoutCreateInfo>(
        VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    set_info.bindingCount = std::uint32_t(layout_bindings.size());
    set_info.pBindings = layout_bindings.data();
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout));
    vk.later([device, set_layout] { vkDestroyDescriptorSetLayout(device, set_layout, nullptr); });
    auto layout_info =
        vk_info<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout;
    VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
    VK_CHECK(vkCreatePipelineLayout(device, &layout_info, nullptr, &pipeline_layout));
    vk.later(
        [device, pipeline_layout] { vkDestroyPipelineLayout(device, pipeline_layout, nullptr); });

    VkShaderModule modules[2] = {};
    const json* stages[2] = {&vert, &frag};
    for (int i = 0; i < 2; ++i) {
        const std::vector<std::uint32_t> words =
            read_words(folder / (*stages[i])["file"].get<std::string>());
        auto info = vk_info<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
        info.codeSize = words.size() * 4;
        info.pCode = words.data();
        VK_CHECK(vkCreateShaderModule(device, &info, nullptr, &modules[i]));
        VkShaderModule m = modules[i];
        vk.later([device, m] { vkDestroyShaderModule(device, m, nullptr); });
    }

    // --- Render targets: linear float colour (the renderer's radiance), depth.
    const VkFormat color_format = VK_FORMAT_R32G32B32A32_SFLOAT;
    const VkFormat depth_format = VK_FORMAT_D32_SFLOAT;
    Texture color, depth;
    ASSERT_NO_FATAL_FAILURE(
        create_image(vk, color_format, kSize, kSize, 1, 1,
                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                     VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_VIEW_TYPE_2D, color));
    ASSERT_NO_FATAL_FAILURE(create_image(vk, depth_format, kSize, kSize, 1, 1,
                                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                         VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_VIEW_TYPE_2D, depth));

    VkAttachmentDescription attachments[2] = {};
    attachments[0].format = color_format;
    attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
    attachments[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    attachments[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    attachments[1] = attachments[0];
    attachments[1].format = depth_format;
    attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &color_ref;
    subpass.pDepthStencilAttachment = &depth_ref;
    VkSubpassDependency dependency{};  // the colour writes before the copy to the host
    dependency.srcSubpass = 0;
    dependency.dstSubpass = VK_SUBPASS_EXTERNAL;
    dependency.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    dependency.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependency.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    auto pass_info = vk_info<VkRenderPassCreateInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO);
    pass_info.attachmentCount = 2;
    pass_info.pAttachments = attachments;
    pass_info.subpassCount = 1;
    pass_info.pSubpasses = &subpass;
    pass_info.dependencyCount = 1;
    pass_info.pDependencies = &dependency;
    VkRenderPass pass = VK_NULL_HANDLE;
    VK_CHECK(vkCreateRenderPass(device, &pass_info, nullptr, &pass));
    vk.later([device, pass] { vkDestroyRenderPass(device, pass, nullptr); });
    VkImageView views[2] = {color.view, depth.view};
    auto fb_info = vk_info<VkFramebufferCreateInfo>(VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO);
    fb_info.renderPass = pass;
    fb_info.attachmentCount = 2;
    fb_info.pAttachments = views;
    fb_info.width = kSize;
    fb_info.height = kSize;
    fb_info.layers = 1;
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    VK_CHECK(vkCreateFramebuffer(device, &fb_info, nullptr, &framebuffer));
    vk.later([device, framebuffer] { vkDestroyFramebuffer(device, framebuffer, nullptr); });

    // --- Pipeline: vertex input from the reflection, the conventions of docs/integration.md
    // (clip-space correction in u_clip, counter-clockwise front faces, back faces culled).
    const scene::Mesh mesh = scene::make_sphere();
    // The vertex layout as a C++ engine reads it (scene::kVertexAttributes), matched by name and
    // location to the stage's reflected inputs.
    std::map<std::string, const scene::VertexAttribute*> vertex_attributes;
    for (const scene::VertexAttribute& a : scene::kVertexAttributes)
        vertex_attributes[std::string("a_") + a.name] = &a;
    std::vector<VkVertexInputAttributeDescription> attributes;
    for (const json& input : vert["reflection"]["inputs"]) {
        const std::string name = input["name"];
        ASSERT_EQ(vertex_attributes.count(name), 1u) << name;
        const scene::VertexAttribute& a = *vertex_attributes[name];
        ASSERT_EQ(input["location"].get<int>(), a.location) << name;
        const VkFormat format = vk_format(input["format"]);
        ASSERT_NE(format, VK_FORMAT_UNDEFINED) << input.dump();
        attributes.push_back({std::uint32_t(a.location), 0, format, std::uint32_t(a.offset)});
    }
    ASSERT_EQ(attributes.size(), std::size(scene::kVertexAttributes));
    const VkVertexInputBindingDescription vertex_binding{0, sizeof(scene::Vertex),
                                                         VK_VERTEX_INPUT_RATE_VERTEX};
    auto vertex_input = vk_info<VkPipelineVertexInputStateCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
    vertex_input.vertexBindingDescriptionCount = 1;
    vertex_input.pVertexBindingDescriptions = &vertex_binding;
    vertex_input.vertexAttributeDescriptionCount = std::uint32_t(attributes.size());
    vertex_input.pVertexAttributeDescriptions = attributes.data();
    auto assembly = vk_info<VkPipelineInputAssemblyStateCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    const VkViewport viewport{0.0f, 0.0f, float(kSize), float(kSize), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {std::uint32_t(kSize), std::uint32_t(kSize)}};
    auto viewport_state = vk_info<VkPipelineViewportStateCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
    viewport_state.viewportCount = 1;
    viewport_state.pViewports = &viewport;
    viewport_state.scissorCount = 1;
    viewport_state.pScissors = &scissor;
    auto raster = vk_info<VkPipelineRasterizationStateCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_BACK_BIT;
    raster.frontFace = front_face;
    raster.lineWidth = 1.0f;
    auto multisample = vk_info<VkPipelineMultisampleStateCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    auto depth_state = vk_info<VkPipelineDepthStencilStateCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
    depth_state.depthTestEnable = VK_TRUE;
    depth_state.depthWriteEnable = VK_TRUE;
    depth_state.depthCompareOp = VK_COMPARE_OP_LESS;
    VkPipelineColorBlendAttachmentState blend_attachment{};
    blend_attachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                      VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    auto blend = vk_info<VkPipelineColorBlendStateCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
    blend.attachmentCount = 1;
    blend.pAttachments = &blend_attachment;
    VkPipelineShaderStageCreateInfo shader_stages[2] = {};
    for (int i = 0; i < 2; ++i) {
        shader_stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        shader_stages[i].stage = i == 0 ? VK_SHADER_STAGE_VERTEX_BIT : VK_SHADER_STAGE_FRAGMENT_BIT;
        shader_stages[i].module = modules[i];
        shader_stages[i].pName =
            (*stages[i])["reflection"]["entry_point"].get_ref<const std::string&>().c_str();
    }
    auto pipeline_info =
        vk_info<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
    pipeline_info.stageCount = 2;
    pipeline_info.pStages = shader_stages;
    pipeline_info.pVertexInputState = &vertex_input;
    pipeline_info.pInputAssemblyState = &assembly;
    pipeline_info.pViewportState = &viewport_state;
    pipeline_info.pRasterizationState = &raster;
    pipeline_info.pMultisampleState = &multisample;
    pipeline_info.pDepthStencilState = &depth_state;
    pipeline_info.pColorBlendState = &blend;
    pipeline_info.layout = pipeline_layout;
    pipeline_info.renderPass = pass;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VK_CHECK(
        vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &pipeline));
    vk.later([device, pipeline] { vkDestroyPipeline(device, pipeline, nullptr); });

    // --- The mesh.
    Buffer vertices, indices;
    ASSERT_NO_FATAL_FAILURE(create_buffer(vk, mesh.vertices.size() * sizeof(scene::Vertex),
                                          VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vertices));
    std::memcpy(vertices.mapped, mesh.vertices.data(),
                mesh.vertices.size() * sizeof(scene::Vertex));
    ASSERT_NO_FATAL_FAILURE(create_buffer(vk, mesh.indices.size() * sizeof(std::uint32_t),
                                          VK_BUFFER_USAGE_INDEX_BUFFER_BIT, indices));
    std::memcpy(indices.mapped, mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));

    // --- The LEAN map: a 2D array of two layers with every level, rows bottom first as the
    // renderer uploads them (+v up, the sphere's uv), and its trilinear repeating sampler.
    const int texel = bytes_per_texel(map.storage);
    Texture lean;
    ASSERT_NO_FATAL_FAILURE(
        create_image(vk, lean_format(map.storage), map.levels[0].width, map.levels[0].height,
                     std::uint32_t(map.levels.size()), 2,
                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                     VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_VIEW_TYPE_2D_ARRAY, lean));
    std::vector<std::vector<std::uint8_t>> lean_data;
    std::vector<VkBufferImageCopy> lean_regions;
    VkDeviceSize offset = 0;
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
        const PackedLevel& l = map.levels[level];
        for (std::uint32_t layer = 0; layer < 2; ++layer) {
            lean_data.push_back(
                flip_rows(layer == 0 ? l.lean1 : l.lean2, l.width, l.height, texel));
            VkBufferImageCopy region{};
            region.bufferOffset = offset;
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, std::uint32_t(level), layer, 1};
            region.imageExtent = {std::uint32_t(l.width), std::uint32_t(l.height), 1};
            lean_regions.push_back(region);
            offset += lean_data.back().size();
        }
    }
    ASSERT_NO_FATAL_FAILURE(upload(vk, lean, lean_data, lean_regions));
    // Base colour: the renderer's fallback for a material without one, a 1x1 white texture.
    Texture white;
    ASSERT_NO_FATAL_FAILURE(
        create_image(vk, VK_FORMAT_R8G8B8A8_UNORM, 1, 1, 1, 1,
                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                     VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_VIEW_TYPE_2D, white));
    VkBufferImageCopy white_region{};
    white_region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    white_region.imageExtent = {1, 1, 1};
    ASSERT_NO_FATAL_FAILURE(upload(vk, white, {{255, 255, 255, 255}}, {white_region}));
    // Base roughness, which the Cook-Torrance variants declare: the material has no map (its bit
    // in u_shading.maps is clear), so any valid texture, here a 1x1 R32F.
    Texture roughness;
    bool reads_roughness = false;
    for (const auto& [number, b] : bindings) reads_roughness |= b.name == "u_base_roughness";
    if (reads_roughness) {
        ASSERT_NO_FATAL_FAILURE(
            create_image(vk, VK_FORMAT_R32_SFLOAT, 1, 1, 1, 1,
                         VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                         VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_VIEW_TYPE_2D, roughness));
        const float one = 1.0f;
        std::vector<std::uint8_t> texel(4);
        std::memcpy(texel.data(), &one, 4);
        ASSERT_NO_FATAL_FAILURE(upload(vk, roughness, {texel}, {white_region}));
    }
    auto sampler_info = vk_info<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
    sampler_info.magFilter = VK_FILTER_LINEAR;
    sampler_info.minFilter = VK_FILTER_LINEAR;
    sampler_info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    sampler_info.addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    sampler_info.addressModeV = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    sampler_info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    sampler_info.mipLodBias = settings.mip_bias;
    sampler_info.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler sampler = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSampler(device, &sampler_info, nullptr, &sampler));
    vk.later([device, sampler] { vkDestroySampler(device, sampler, nullptr); });

    // --- The uniform blocks, as the renderer fills them (Renderer::draw_scene), after checking
    // the reflected layout against the C++ mirrors.
    const gl::View view = gl::view_at_distance(distance);
    const float aspect = 1.0f;
    // Vulkan's clip space: y down, depth 0..1 (docs/integration.md): u_clip carries the change.
    const glm::mat4 vulkan_clip(1.0f, 0.0f, 0.0f, 0.0f,   // column 0
                                0.0f, -1.0f, 0.0f, 0.0f,  // column 1
                                0.0f, 0.0f, 0.5f, 0.0f,   // column 2
                                0.0f, 0.0f, 0.5f, 1.0f);  // column 3
    gl::LfObjectUniforms object{};
    const float radius = mesh.bounds.radius();
    object.model = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / radius)) *
                   glm::translate(glm::mat4(1.0f), -mesh.bounds.center());
    object.view = view.view_matrix();
    object.clip = vulkan_clip * view.projection_matrix(aspect) * view.view_matrix();
    const glm::mat3 normal_matrix(glm::transpose(glm::inverse(object.model)));
    for (int c = 0; c < 3; ++c) object.normal_matrix[c] = glm::vec4(normal_matrix[c], 0.0f);
    object.eye_world = view.eye;
    object.tiling = settings.tiling;
    object.light_world = glm::normalize(settings.light_direction);
    // The shading block as docs/integration.md tells an engine to fill it: its defaults (valid:
    // identity uv transforms, the parameter table's values), the settings' parameters, the map's
    // sc and encoding offset. Not gl::shading_uniforms: an engine does not link the GL component.
    shading::LfShadingUniforms shading;
    shading.params = to_lf_params(settings, map.roughness_baked);
    shading.scale = map.scale;
    shading.lean_offset = lean_offset(map.encoding);

    struct Block {
        const void* data;
        std::size_t size;
        std::vector<gl::BlockMember> members;
    };
    const std::map<std::string, Block> blocks{
        {"LfObjectBlock", {&object, sizeof(object), gl::object_block_members()}},
        {"LfShadingBlock", {&shading, sizeof(shading), gl::shading_block_members()}}};
    for (const json* stage : stages)
        for (const json& r : (*stage)["reflection"]["resources"])
            if (r["descriptor_type"] == "uniform_buffer") {
                const auto it = blocks.find(r["name"]);
                ASSERT_NE(it, blocks.end()) << r.dump();
                expect_block_matches(r, it->second.members);
                EXPECT_LE(r["block_size"].get<std::size_t>(), it->second.size) << r["name"];
            }

    // --- Descriptors: each binding of the layout by its name, nothing else.
    std::vector<VkDescriptorPoolSize> pool_sizes;
    for (const auto& [number, b] : bindings)
        pool_sizes.push_back({b.layout.descriptorType, b.layout.descriptorCount});
    auto pool_info =
        vk_info<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = std::uint32_t(pool_sizes.size());
    pool_info.pPoolSizes = pool_sizes.data();
    VkDescriptorPool descriptor_pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorPool(device, &pool_info, nullptr, &descriptor_pool));
    vk.later(
        [device, descriptor_pool] { vkDestroyDescriptorPool(device, descriptor_pool, nullptr); });
    auto set_alloc =
        vk_info<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
    set_alloc.descriptorPool = descriptor_pool;
    set_alloc.descriptorSetCount = 1;
    set_alloc.pSetLayouts = &set_layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateDescriptorSets(device, &set_alloc, &set));
    std::vector<Buffer> uniform_buffers(bindings.size());
    std::vector<VkDescriptorBufferInfo> buffer_infos(bindings.size());
    std::vector<VkDescriptorImageInfo> image_infos(bindings.size());
    std::vector<VkWriteDescriptorSet> writes;
    std::size_t slot = 0;
    for (const auto& [number, b] : bindings) {
        auto w = vk_info<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
        w.dstSet = set;
        w.dstBinding = number;
        w.descriptorCount = 1;
        w.descriptorType = b.layout.descriptorType;
        ASSERT_EQ(b.layout.descriptorCount, 1u) << b.name;
        if (b.layout.descriptorType == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER) {
            const Block& block = blocks.at(b.name);
            ASSERT_NO_FATAL_FAILURE(create_buffer(
                vk, block.size, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, uniform_buffers[slot]));
            std::memcpy(uniform_buffers[slot].mapped, block.data, block.size);
            buffer_infos[slot] = {uniform_buffers[slot].buffer, 0, block.size};
            w.pBufferInfo = &buffer_infos[slot];
        } else {
            // The glTF material maps: the renderer's white fallback (metallic, occlusion and
            // emissive times factors of 0) or, for the anisotropy texture and the specular map
            // whose bits are clear, any valid texture.
            const bool white_fallback = b.name == "u_base_color" || b.name == "u_metallic" ||
                                        b.name == "u_occlusion" || b.name == "u_emissive" ||
                                        b.name == "u_anisotropy" || b.name == "u_specular";
            const Texture* texture = b.name == "u_lean"             ? &lean
                                     : white_fallback               ? &white
                                     : b.name == "u_base_roughness" ? &roughness
                                                                    : nullptr;
            ASSERT_NE(texture, nullptr) << "a texture the test does not have: " << b.name;
            image_infos[slot] = {sampler, texture->view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            w.pImageInfo = &image_infos[slot];
        }
        writes.push_back(w);
        ++slot;
    }
    vkUpdateDescriptorSets(device, std::uint32_t(writes.size()), writes.data(), 0, nullptr);

    // --- Draw and read back.
    Buffer readback;
    ASSERT_NO_FATAL_FAILURE(create_buffer(vk, VkDeviceSize(kSize) * kSize * 16,
                                          VK_BUFFER_USAGE_TRANSFER_DST_BIT, readback));
    submit(vk, [&](VkCommandBuffer cmd) {
        VkClearValue clears[2] = {};
        const glm::vec3 background = gl::FigureRequest{}.background;  // the figures'
        clears[0].color = {{background.r, background.g, background.b, 1.0f}};
        clears[1].depthStencil = {1.0f, 0};
        auto begin = vk_info<VkRenderPassBeginInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO);
        begin.renderPass = pass;
        begin.framebuffer = framebuffer;
        begin.renderArea = scissor;
        begin.clearValueCount = 2;
        begin.pClearValues = clears;
        vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_layout, 0, 1, &set,
                                0, nullptr);
        const VkDeviceSize zero = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vertices.buffer, &zero);
        vkCmdBindIndexBuffer(cmd, indices.buffer, 0, VK_INDEX_TYPE_UINT32);
        vkCmdDrawIndexed(cmd, std::uint32_t(mesh.indices.size()), 1, 0, 0, 0);
        vkCmdEndRenderPass(cmd);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {std::uint32_t(kSize), std::uint32_t(kSize), 1};
        vkCmdCopyImageToBuffer(cmd, color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                               readback.buffer, 1, &region);
        auto to_host = vk_info<VkBufferMemoryBarrier>(VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER);
        to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        to_host.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        to_host.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        to_host.buffer = readback.buffer;
        to_host.size = VK_WHOLE_SIZE;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0,
                             nullptr, 1, &to_host, 0, nullptr);
    });
    // Vulkan's row 0 is the top row, as the renderer's images.
    frame.image = Image(kSize, kSize, 3);
    const float* texels = static_cast<const float*>(readback.mapped);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            for (int c = 0; c < 3; ++c)
                frame.image.pixels[frame.image.index(x, y, c)] =
                    texels[(std::size_t(y) * kSize + std::size_t(x)) * 4 + std::size_t(c)];
    device_name_ = vk.device_name;
}

Image cell(const fs::path& folder, Technique technique, float distance) {
    const fs::path file =
        folder / (std::string(to_string(technique)) + "_d" + gl::distance_text(distance) + ".pfm");
    return io::read_image(file.string());
}

TEST_F(VulkanConsumer, ExportedSpirvDrawsTheSphereAsLeanfadeRenderWithoutValidationMessages) {
    const ShadingSettings settings;
    int modules = 0;
    std::string figures;
    for (const Technique technique : {Technique::Bump, Technique::Lean, Technique::Fade}) {
        const std::string variant = renderer_variant(technique, settings);
        for (const float distance : {3.0f, 12.0f}) {
            Frame frame;
            ASSERT_NO_FATAL_FAILURE(
                draw(variant, distance, VK_FRONT_FACE_COUNTER_CLOCKWISE, frame));
            const Image reference = cell(*scratch_ / "cells", technique, distance);
            ASSERT_EQ(reference.width, kSize);
            ASSERT_EQ(reference.height, kSize);
            const CellComparison c = compare_cells(frame.image, reference);
            // Beside the cells, for a look when the figures are off.
            io::write_png(
                (*scratch_ / ("vulkan_" + variant + "_d" + gl::distance_text(distance) + ".png"))
                    .string(),
                eval::encode_srgb(frame.image), 8);
            char line[400];
            std::snprintf(line, sizeof line,
                          "vulkan %-22s d=%-3g on %s: %d validation messages; vs leanfade render: "
                          "RMSE %.3f 8-bit codes over the object (%.1f%% of the cell), %.3f over "
                          "the cell, max %d\n",
                          variant.c_str(), distance, device_name_.c_str(), frame.messages.count,
                          c.object_rmse, 100.0 * c.covered, c.rmse, c.max_difference);
            std::fputs(line, stdout);
            figures += line;
            EXPECT_EQ(frame.messages.count, 0) << testing::PrintToString(frame.messages.texts);
            EXPECT_LE(c.object_rmse, 0.5) << variant << " at " << distance;
            // Not a comparison of two empty images: the sphere covers the cell's middle.
            EXPECT_GT(c.covered, distance < 5.0f ? 0.25 : 0.01) << variant;
            ++modules;
        }
    }
    // Cook-Torrance: its variant has the base roughness binding as well.
    ShadingSettings ct;
    ct.brdf = Brdf::CookTorrance;
    const std::string variant = renderer_variant(Technique::Lean, ct);
    EXPECT_EQ(variant, "scene_lean_plain_ct");
    Frame frame;
    ASSERT_NO_FATAL_FAILURE(draw(variant, 3.0f, VK_FRONT_FACE_COUNTER_CLOCKWISE, frame, ct));
    const CellComparison c = compare_cells(frame.image, cell(*scratch_ / "cells_ct", Technique::Lean, 3.0f));
    char line[400];
    std::snprintf(line, sizeof line,
                  "vulkan %-22s d=%-3d on %s: %d validation messages; vs leanfade render: RMSE "
                  "%.3f 8-bit codes over the object (%.1f%% of the cell), %.3f over the cell, "
                  "max %d\n",
                  variant.c_str(), 3, device_name_.c_str(), frame.messages.count, c.object_rmse,
                  100.0 * c.covered, c.rmse, c.max_difference);
    std::fputs(line, stdout);
    figures += line;
    EXPECT_EQ(frame.messages.count, 0) << testing::PrintToString(frame.messages.texts);
    EXPECT_LE(c.object_rmse, 0.5) << variant;
    EXPECT_GT(c.covered, 0.25) << variant;
    EXPECT_EQ(modules, 6);
    // The figures also go to the build's test folder, for a report after the run (ctest shows a
    // passing test's output only when verbose).
    std::ofstream(fs::path(LEANFADE_TEST_TMP) / "vulkan_figures.txt") << figures;
}

// The winding the docs give is the one that draws the outside: with clockwise front faces the
// same pipeline culls the near hemisphere and shows the inside of the far one.
TEST_F(VulkanConsumer, ClockwiseFrontFacesShowTheInsideInstead) {
    const ShadingSettings settings;
    const std::string variant = renderer_variant(Technique::Lean, settings);
    Frame frame;
    ASSERT_NO_FATAL_FAILURE(draw(variant, 3.0f, VK_FRONT_FACE_CLOCKWISE, frame));
    const CellComparison c = compare_cells(frame.image, cell(*scratch_ / "cells", Technique::Lean, 3.0f));
    std::printf("vulkan %s with clockwise front faces: RMSE %.3f 8-bit codes\n", variant.c_str(),
                c.rmse);
    EXPECT_GT(c.rmse, 5.0);
    EXPECT_EQ(frame.messages.count, 0) << testing::PrintToString(frame.messages.texts);
}

// The count of 0 above means something: the same messenger counts the layer's report of an
// invalid call (anisotropic filtering asked of a sampler on a device created without the
// feature: VUID-VkSamplerCreateInfo-anisotropyEnable-01070).
TEST(VulkanValidation, TheMessengerCountsTheLayersReports) {
    const fs::path icd = lavapipe_icd();
    ASSERT_FALSE(icd.empty()) << "lavapipe's ICD file is missing (mesa-vulkan-drivers)";
    use_lavapipe();
    Messages messages;
    {
        Vulkan vk(messages);
        ASSERT_NO_FATAL_FAILURE(create_vulkan(vk));
        EXPECT_EQ(messages.count, 0) << testing::PrintToString(messages.texts);
        auto info = vk_info<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
        info.anisotropyEnable = VK_TRUE;
        info.maxAnisotropy = 16.0f;
        VkSampler sampler = VK_NULL_HANDLE;
        if (vkCreateSampler(vk.device, &info, nullptr, &sampler) == VK_SUCCESS)
            vkDestroySampler(vk.device, sampler, nullptr);
    }
    EXPECT_GE(messages.count, 1);
    EXPECT_THAT(testing::PrintToString(messages.texts), testing::HasSubstr("anisotropyEnable"));
}

}  // namespace
}  // namespace leanfade::test
