// SPDX-License-Identifier: MIT
// A small OpenXR runtime for the tests (docs/xr.md, "Tests"): loaded by the real Khronos
// loader through XR_RUNTIME_JSON, it plays a scripted head and controllers and writes what the
// application submits to a log the tests read back. No display: swapchain images are real GL
// textures in the application's context, read back at xrEndFrame to see that both eyes were
// drawn.
//
// Environment:
//   VSCULPT_TEST_XR_SCRIPT  the script (below); none: everything at rest
//   VSCULPT_TEST_XR_LOG     where the log goes (appended, one event a line)
//   VSCULPT_TEST_XR_NO_HMD  set: xrGetSystem says the headset is not connected
//   VSCULPT_TEST_XR_DUMP    PREFIX: each read-back eye image also goes to PREFIX-eyeN.ppm
//                           (for a person to look at)
//
// Script, one command a line, `#` comments. `at F ...` holds from frame F on (frames count
// xrWaitFrame calls from 0):
//   profile PATH                        the controllers' interaction profile (default Index)
//   view W H                            recommended eye image size (default 256 x 256)
//   at F head X Y Z QX QY QZ QW         head pose in local space (metres)
//   at F left|right X Y Z QX QY QZ QW   a hand's grip and aim pose
//   at F PATH VALUE                     an input, e.g. /user/hand/right/input/trigger/value 1
//   at F exit                           the runtime stops the session (a user quitting)
//   at F lose                           the session is lost (loss pending)
#include <GL/gl.h>
#include <openxr/openxr.h>
#include <openxr/openxr_reflection.h>

#define XR_USE_GRAPHICS_API_OPENGL
#define XR_USE_PLATFORM_XLIB
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <openxr/openxr_platform.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

// The loader <-> runtime negotiation structures (OpenXR loader specification, "Runtime
// Interface Negotiation"); Debian's headers do not carry loader_interfaces.h.
enum XrLoaderInterfaceStructs {
    XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
    XR_LOADER_INTERFACE_STRUCT_LOADER_INFO,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST,
    XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST,
};
struct XrNegotiateLoaderInfo {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t minInterfaceVersion, maxInterfaceVersion;
    XrVersion minApiVersion, maxApiVersion;
};
struct XrNegotiateRuntimeRequest {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t runtimeInterfaceVersion;
    XrVersion runtimeApiVersion;
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;
};

namespace {

constexpr int64_t kPeriodNs = 11'111'111;  // 90 Hz
constexpr int64_t kStartNs = 1'000'000'000;
constexpr uint8_t kBackground[3] = {26, 28, 38};  // vsculpt's clear colour (render/Shot.h)

struct Pose {
    glm::dvec3 p{0.0};
    glm::dquat q{1, 0, 0, 0};
};

struct Keyed {
    int frame;
    std::string key;  // "head", "left", "right", an input path, "exit", "lose"
    Pose pose;
    double value = 0;
};

struct Swapchain {
    std::vector<GLuint> textures;
    int width = 0, height = 0;
    uint32_t next = 0, acquired = 0;
    int lastReleased = -1, releasedThisFrame = 0;
};
struct Space {
    enum { Local, View, Action } kind = Local;
    XrAction action = XR_NULL_HANDLE;
};
struct Action {
    std::string name;
    XrActionType type;
    bool lastBool = false;
    float lastFloat = 0;
    bool changed = false;
};

struct Runtime {
    std::FILE* log = nullptr;
    std::vector<Keyed> script;
    std::string profile = "/interaction_profiles/valve/index_controller";
    int viewW = 256, viewH = 256;
    std::vector<std::string> paths{""};  // XrPath n is paths[n]
    std::deque<XrSessionState> events;
    bool sessionRunning = false, focusedSent = false, exitQueued = false, lossQueued = false,
         sessionExists = false, requirementsAsked = false, profileEventSent = false;
    int64_t frame = -1;  // xrWaitFrame calls so far - 1
    int64_t endedFrames = 0;
    std::map<XrPath, std::map<XrAction, std::vector<XrPath>>> bindings;  // profile -> action
    std::set<XrAction> attachedActions;
    std::map<XrAction, std::unique_ptr<Action>> actions;
    std::map<XrSwapchain, std::unique_ptr<Swapchain>> swapchains;
    std::map<XrSpace, std::unique_ptr<Space>> spaces;
    std::set<XrActionSet> actionSets;
    // The inputs as synced by the last xrSyncActions.
    std::map<std::string, double> synced;
    int hapticCalls = 0;
};

Runtime* rt = nullptr;
int instanceTag = 0, sessionTag = 0;

void logLine(const char* fmt, ...) {
    if (!rt || !rt->log) return;
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(rt->log, fmt, ap);
    va_end(ap);
    std::fputc('\n', rt->log);
    std::fflush(rt->log);
}

const char* stateName(XrSessionState s) {
    switch (s) {
        case XR_SESSION_STATE_IDLE:
            return "idle";
        case XR_SESSION_STATE_READY:
            return "ready";
        case XR_SESSION_STATE_SYNCHRONIZED:
            return "synchronized";
        case XR_SESSION_STATE_VISIBLE:
            return "visible";
        case XR_SESSION_STATE_FOCUSED:
            return "focused";
        case XR_SESSION_STATE_STOPPING:
            return "stopping";
        case XR_SESSION_STATE_LOSS_PENDING:
            return "loss_pending";
        case XR_SESSION_STATE_EXITING:
            return "exiting";
        default:
            return "unknown";
    }
}

void queue(XrSessionState s) {
    rt->events.push_back(s);
    logLine("state %s", stateName(s));
}

void loadScript(const char* path) {
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        if (auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream s(line);
        std::string word;
        if (!(s >> word)) continue;
        if (word == "profile") {
            s >> rt->profile;
        } else if (word == "view") {
            s >> rt->viewW >> rt->viewH;
        } else if (word == "at") {
            Keyed k;
            s >> k.frame >> k.key;
            if (k.key == "head" || k.key == "left" || k.key == "right") {
                double x, y, z, qx, qy, qz, qw;
                s >> x >> y >> z >> qx >> qy >> qz >> qw;
                k.pose = {{x, y, z}, glm::normalize(glm::dquat(qw, qx, qy, qz))};
            } else if (k.key != "exit" && k.key != "lose") {
                s >> k.value;
            }
            rt->script.push_back(k);
        }
    }
}

int64_t frameAt(XrTime time) {
    return std::max<int64_t>(0, (time - kStartNs) / kPeriodNs - 1);
}

Pose poseAt(const std::string& key, int64_t frame) {
    Pose p;
    if (key == "head") p.p = {0, 0, 0};
    for (const Keyed& k : rt->script)
        if (k.key == key && k.frame <= frame) p = k.pose;
    return p;
}

double inputAt(const std::string& path, int64_t frame) {
    double v = 0;
    for (const Keyed& k : rt->script)
        if (k.key == path && k.frame <= frame) v = k.value;
    return v;
}

XrPath pathOf(const std::string& s) {
    for (size_t i = 1; i < rt->paths.size(); ++i)
        if (rt->paths[i] == s) return XrPath(i);
    rt->paths.push_back(s);
    return XrPath(rt->paths.size() - 1);
}

// The bound input paths of `action` in the current profile.
std::vector<std::string> boundInputs(XrAction action) {
    std::vector<std::string> out;
    for (size_t i = 1; i < rt->paths.size(); ++i)
        if (rt->paths[i] == rt->profile) {
            const auto& perAction = rt->bindings[XrPath(i)];
            if (auto it = perAction.find(action); it != perAction.end())
                for (XrPath p : it->second)
                    out.push_back(rt->paths[p]);
        }
    return out;
}

XrPosef toXr(const Pose& p) {
    XrPosef x;
    x.position = {float(p.p.x), float(p.p.y), float(p.p.z)};
    x.orientation = {float(p.q.x), float(p.q.y), float(p.q.z), float(p.q.w)};
    return x;
}

// ---- instance ----------------------------------------------------------------------------

XrResult XRAPI_CALL enumerateExtensions(const char* layer, uint32_t capacity, uint32_t* count,
                                        XrExtensionProperties* props) {
    if (layer) return XR_ERROR_API_LAYER_NOT_PRESENT;
    const char* names[] = {XR_KHR_OPENGL_ENABLE_EXTENSION_NAME};
    *count = 1;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 1) return XR_ERROR_SIZE_INSUFFICIENT;
    std::strcpy(props[0].extensionName, names[0]);
    props[0].extensionVersion = XR_KHR_opengl_enable_SPEC_VERSION;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL createInstance(const XrInstanceCreateInfo* info, XrInstance* instance) {
    for (uint32_t i = 0; i < info->enabledExtensionCount; ++i)
        if (std::strcmp(info->enabledExtensionNames[i], XR_KHR_OPENGL_ENABLE_EXTENSION_NAME) != 0)
            return XR_ERROR_EXTENSION_NOT_PRESENT;
    delete rt;
    rt = new Runtime;
    if (const char* l = std::getenv("VSCULPT_TEST_XR_LOG")) rt->log = std::fopen(l, "a");
    if (const char* s = std::getenv("VSCULPT_TEST_XR_SCRIPT")) loadScript(s);
    *instance = reinterpret_cast<XrInstance>(&instanceTag);
    logLine("instance %s", info->applicationInfo.applicationName);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL destroyInstance(XrInstance) {
    logLine("destroy instance");
    if (rt && rt->log) std::fclose(rt->log);
    delete rt;
    rt = nullptr;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL getInstanceProperties(XrInstance, XrInstanceProperties* p) {
    p->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
    std::strcpy(p->runtimeName, "vsculpt test runtime");
    return XR_SUCCESS;
}

XrResult XRAPI_CALL resultToString(XrInstance, XrResult value,
                                   char buffer[XR_MAX_RESULT_STRING_SIZE]) {
#define VSCULPT_RESULT_CASE(name, val)                                 \
    case name:                                                         \
        std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "%s", #name); \
        return XR_SUCCESS;
    switch (value) {
        XR_LIST_ENUM_XrResult(VSCULPT_RESULT_CASE) default
            : std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "XR_UNKNOWN_%d", int(value));
    }
#undef VSCULPT_RESULT_CASE
    return XR_SUCCESS;
}

XrResult XRAPI_CALL structureTypeToString(XrInstance, XrStructureType value,
                                          char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
#define VSCULPT_TYPE_CASE(name, val)                                    \
    case name:                                                          \
        std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "%s", #name); \
        return XR_SUCCESS;
    switch (value) {
        XR_LIST_ENUM_XrStructureType(VSCULPT_TYPE_CASE) default
            : std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_UNKNOWN_STRUCTURE_TYPE_%d",
                            int(value));
    }
#undef VSCULPT_TYPE_CASE
    return XR_SUCCESS;
}

XrResult XRAPI_CALL pollEvent(XrInstance, XrEventDataBuffer* buffer) {
    if (!rt->events.empty()) {
        auto* e = reinterpret_cast<XrEventDataSessionStateChanged*>(buffer);
        e->type = XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED;
        e->next = nullptr;
        e->session = reinterpret_cast<XrSession>(&sessionTag);
        e->state = rt->events.front();
        e->time = kStartNs + (rt->frame + 1) * kPeriodNs;
        rt->events.pop_front();
        return XR_SUCCESS;
    }
    return XR_EVENT_UNAVAILABLE;
}

XrResult XRAPI_CALL getSystem(XrInstance, const XrSystemGetInfo* info, XrSystemId* id) {
    if (info->formFactor != XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY)
        return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
    if (std::getenv("VSCULPT_TEST_XR_NO_HMD")) return XR_ERROR_FORM_FACTOR_UNAVAILABLE;
    *id = 1;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL getSystemProperties(XrInstance, XrSystemId, XrSystemProperties* p) {
    p->systemId = 1;
    p->vendorId = 0;
    std::strcpy(p->systemName, "scripted test headset");
    p->graphicsProperties = {4096, 4096, 16};
    p->trackingProperties = {XR_TRUE, XR_TRUE};
    return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerateViewConfigurations(XrInstance, XrSystemId, uint32_t capacity,
                                                uint32_t* count, XrViewConfigurationType* types) {
    *count = 1;
    if (capacity >= 1) types[0] = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL getViewConfigurationProperties(XrInstance, XrSystemId, XrViewConfigurationType,
                                                   XrViewConfigurationProperties* p) {
    p->viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    p->fovMutable = XR_FALSE;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerateViewConfigurationViews(XrInstance, XrSystemId, XrViewConfigurationType,
                                                    uint32_t capacity, uint32_t* count,
                                                    XrViewConfigurationView* views) {
    *count = 2;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 2) return XR_ERROR_SIZE_INSUFFICIENT;
    for (int i = 0; i < 2; ++i) {
        views[i].recommendedImageRectWidth = uint32_t(rt->viewW);
        views[i].recommendedImageRectHeight = uint32_t(rt->viewH);
        views[i].maxImageRectWidth = 4096;
        views[i].maxImageRectHeight = 4096;
        views[i].recommendedSwapchainSampleCount = 1;
        views[i].maxSwapchainSampleCount = 1;
    }
    return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerateBlendModes(XrInstance, XrSystemId, XrViewConfigurationType,
                                        uint32_t capacity, uint32_t* count,
                                        XrEnvironmentBlendMode* m) {
    *count = 1;
    if (capacity >= 1) m[0] = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL glRequirements(XrInstance, XrSystemId, XrGraphicsRequirementsOpenGLKHR* r) {
    r->minApiVersionSupported = XR_MAKE_VERSION(3, 3, 0);
    r->maxApiVersionSupported = XR_MAKE_VERSION(4, 6, 0);
    rt->requirementsAsked = true;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL stringToPath(XrInstance, const char* s, XrPath* path) {
    if (!s || s[0] != '/') return XR_ERROR_PATH_FORMAT_INVALID;
    *path = pathOf(s);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL pathToString(XrInstance, XrPath path, uint32_t capacity, uint32_t* count,
                                 char* buffer) {
    if (path == 0 || path >= rt->paths.size()) return XR_ERROR_PATH_INVALID;
    const std::string& s = rt->paths[path];
    *count = uint32_t(s.size() + 1);
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < *count) return XR_ERROR_SIZE_INSUFFICIENT;
    std::memcpy(buffer, s.c_str(), s.size() + 1);
    return XR_SUCCESS;
}

// ---- session -----------------------------------------------------------------------------

XrResult XRAPI_CALL createSession(XrInstance, const XrSessionCreateInfo* info, XrSession* session) {
    if (!rt->requirementsAsked) return XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
    const auto* b = static_cast<const XrGraphicsBindingOpenGLXlibKHR*>(info->next);
    if (!b || b->type != XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR)
        return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    // The binding must name the context that is current: the swapchain images are made in it.
    if (!b->xDisplay || !b->glxContext || glXGetCurrentContext() != b->glxContext) {
        logLine("binding rejected: context %p current %p", (void*)b->glxContext,
                (void*)glXGetCurrentContext());
        return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    }
    logLine("session glx drawable %s fbconfig %s", b->glxDrawable ? "yes" : "no",
            b->glxFBConfig ? "yes" : "no");
    rt->sessionExists = true;
    *session = reinterpret_cast<XrSession>(&sessionTag);
    queue(XR_SESSION_STATE_IDLE);
    queue(XR_SESSION_STATE_READY);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL destroySession(XrSession) {
    rt->sessionExists = false;
    logLine("destroy session");
    return XR_SUCCESS;
}

XrResult XRAPI_CALL beginSession(XrSession, const XrSessionBeginInfo* info) {
    if (info->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
        return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    rt->sessionRunning = true;
    logLine("begin session");
    return XR_SUCCESS;
}

XrResult XRAPI_CALL endSession(XrSession) {
    rt->sessionRunning = false;
    logLine("end session");
    queue(XR_SESSION_STATE_IDLE);
    queue(XR_SESSION_STATE_EXITING);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL requestExitSession(XrSession) {
    logLine("request exit");
    if (!rt->exitQueued) queue(XR_SESSION_STATE_STOPPING);
    rt->exitQueued = true;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerateReferenceSpaces(XrSession, uint32_t capacity, uint32_t* count,
                                             XrReferenceSpaceType* types) {
    *count = 2;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 2) return XR_ERROR_SIZE_INSUFFICIENT;
    types[0] = XR_REFERENCE_SPACE_TYPE_VIEW;
    types[1] = XR_REFERENCE_SPACE_TYPE_LOCAL;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL createReferenceSpace(XrSession, const XrReferenceSpaceCreateInfo* info,
                                         XrSpace* space) {
    auto s = std::make_unique<Space>();
    if (info->referenceSpaceType == XR_REFERENCE_SPACE_TYPE_LOCAL)
        s->kind = Space::Local;
    else if (info->referenceSpaceType == XR_REFERENCE_SPACE_TYPE_VIEW)
        s->kind = Space::View;
    else
        return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
    *space = reinterpret_cast<XrSpace>(s.get());
    rt->spaces[*space] = std::move(s);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL createActionSpace(XrSession, const XrActionSpaceCreateInfo* info,
                                      XrSpace* space) {
    auto s = std::make_unique<Space>();
    s->kind = Space::Action;
    s->action = info->action;
    *space = reinterpret_cast<XrSpace>(s.get());
    rt->spaces[*space] = std::move(s);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL destroySpace(XrSpace space) {
    rt->spaces.erase(space);
    return XR_SUCCESS;
}

// The hand an action's bindings belong to in the current profile ("" when unbound).
std::string handOf(XrAction action) {
    for (const std::string& p : boundInputs(action)) {
        if (p.rfind("/user/hand/right/", 0) == 0) return "right";
        if (p.rfind("/user/hand/left/", 0) == 0) return "left";
    }
    return "";
}

bool poseInLocal(XrSpace space, XrTime time, Pose& out) {
    const Space& s = *rt->spaces.at(space);
    const int64_t f = frameAt(time);
    if (s.kind == Space::Local) {
        out = Pose{};
        return true;
    }
    if (s.kind == Space::View) {
        out = poseAt("head", f);
        return true;
    }
    const std::string hand = handOf(s.action);
    if (hand.empty()) return false;
    out = poseAt(hand, f);
    return true;
}

XrResult XRAPI_CALL locateSpace(XrSpace space, XrSpace base, XrTime time, XrSpaceLocation* loc) {
    Pose a, b;
    loc->locationFlags = 0;
    if (!poseInLocal(space, time, a) || !poseInLocal(base, time, b)) return XR_SUCCESS;
    const glm::dquat bi = glm::inverse(b.q);
    Pose rel{bi * (a.p - b.p), bi * a.q};
    loc->pose = toXr(rel);
    loc->locationFlags =
        XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT |
        XR_SPACE_LOCATION_POSITION_TRACKED_BIT | XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
    return XR_SUCCESS;
}

// ---- swapchains --------------------------------------------------------------------------

XrResult XRAPI_CALL enumerateSwapchainFormats(XrSession, uint32_t capacity, uint32_t* count,
                                              int64_t* formats) {
    *count = 2;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 2) return XR_ERROR_SIZE_INSUFFICIENT;
    formats[0] = 0x8C43;  // GL_SRGB8_ALPHA8: runtimes list it first
    formats[1] = GL_RGBA8;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL createSwapchain(XrSession, const XrSwapchainCreateInfo* info,
                                    XrSwapchain* out) {
    auto sc = std::make_unique<Swapchain>();
    sc->width = int(info->width);
    sc->height = int(info->height);
    sc->textures.resize(3);
    // Real textures in the application's current context, as a compositor would share them.
    glGenTextures(3, sc->textures.data());
    for (GLuint t : sc->textures) {
        glBindTexture(GL_TEXTURE_2D, t);
        glTexImage2D(GL_TEXTURE_2D, 0, GLint(info->format), sc->width, sc->height, 0, GL_RGBA,
                     GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    if (glGetError() != GL_NO_ERROR) return XR_ERROR_RUNTIME_FAILURE;
    *out = reinterpret_cast<XrSwapchain>(sc.get());
    logLine("swapchain %dx%d format 0x%llx", sc->width, sc->height, (long long)info->format);
    rt->swapchains[*out] = std::move(sc);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL destroySwapchain(XrSwapchain s) {
    auto it = rt->swapchains.find(s);
    if (it == rt->swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    glDeleteTextures(GLsizei(it->second->textures.size()), it->second->textures.data());
    rt->swapchains.erase(it);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerateSwapchainImages(XrSwapchain s, uint32_t capacity, uint32_t* count,
                                             XrSwapchainImageBaseHeader* images) {
    const Swapchain& sc = *rt->swapchains.at(s);
    *count = uint32_t(sc.textures.size());
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < *count) return XR_ERROR_SIZE_INSUFFICIENT;
    auto* gl = reinterpret_cast<XrSwapchainImageOpenGLKHR*>(images);
    for (uint32_t i = 0; i < *count; ++i)
        gl[i].image = sc.textures[i];
    return XR_SUCCESS;
}

XrResult XRAPI_CALL acquireImage(XrSwapchain s, const XrSwapchainImageAcquireInfo*,
                                 uint32_t* index) {
    Swapchain& sc = *rt->swapchains.at(s);
    *index = sc.next;
    sc.next = (sc.next + 1) % uint32_t(sc.textures.size());
    ++sc.acquired;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL waitImage(XrSwapchain, const XrSwapchainImageWaitInfo*) {
    return XR_SUCCESS;
}

XrResult XRAPI_CALL releaseImage(XrSwapchain s, const XrSwapchainImageReleaseInfo*) {
    Swapchain& sc = *rt->swapchains.at(s);
    sc.lastReleased = int((sc.next + sc.textures.size() - 1) % sc.textures.size());
    ++sc.releasedThisFrame;
    return XR_SUCCESS;
}

// ---- frames ------------------------------------------------------------------------------

XrResult XRAPI_CALL waitFrame(XrSession, const XrFrameWaitInfo*, XrFrameState* state) {
    ++rt->frame;
    state->predictedDisplayPeriod = kPeriodNs;
    state->predictedDisplayTime = kStartNs + (rt->frame + 1) * kPeriodNs;
    state->shouldRender = XR_TRUE;
    for (const Keyed& k : rt->script) {
        if (k.frame != rt->frame) continue;
        if (k.key == "exit" && !rt->exitQueued) {
            rt->exitQueued = true;
            queue(XR_SESSION_STATE_STOPPING);
        }
        if (k.key == "lose" && !rt->lossQueued) {
            rt->lossQueued = true;
            queue(XR_SESSION_STATE_LOSS_PENDING);
        }
    }
    return XR_SUCCESS;
}

XrResult XRAPI_CALL beginFrame(XrSession, const XrFrameBeginInfo*) {
    for (auto& [h, sc] : rt->swapchains)
        sc->releasedThisFrame = 0;
    return XR_SUCCESS;
}

// Pixels of a texture that are not the clear colour: something was drawn.
long litPixels(const Swapchain& sc, int eye) {
    if (sc.lastReleased < 0) return -1;
    std::vector<uint8_t> px(size_t(sc.width) * size_t(sc.height) * 4);
    glBindTexture(GL_TEXTURE_2D, sc.textures[size_t(sc.lastReleased)]);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    if (const char* dump = std::getenv("VSCULPT_TEST_XR_DUMP")) {
        const std::string path = std::string(dump) + "-eye" + std::to_string(eye) + ".ppm";
        if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
            std::fprintf(f, "P6 %d %d 255\n", sc.width, sc.height);
            // GL rows go bottom-up; PPM rows top-down.
            for (int y = sc.height - 1; y >= 0; --y)
                for (int x = 0; x < sc.width; ++x)
                    std::fwrite(&px[(size_t(y) * size_t(sc.width) + size_t(x)) * 4], 1, 3, f);
            std::fclose(f);
        }
    }
    long lit = 0;
    for (size_t i = 0; i < px.size(); i += 4)
        if (std::abs(int(px[i]) - kBackground[0]) > 2 ||
            std::abs(int(px[i + 1]) - kBackground[1]) > 2 ||
            std::abs(int(px[i + 2]) - kBackground[2]) > 2)
            ++lit;
    return lit;
}

XrResult XRAPI_CALL endFrame(XrSession, const XrFrameEndInfo* info) {
    std::string what;
    for (uint32_t i = 0; i < info->layerCount; ++i) {
        const XrCompositionLayerBaseHeader* l = info->layers[i];
        if (l->type == XR_TYPE_COMPOSITION_LAYER_QUAD) {
            const auto* q = reinterpret_cast<const XrCompositionLayerQuad*>(l);
            auto it = rt->swapchains.find(q->subImage.swapchain);
            if (it == rt->swapchains.end()) return XR_ERROR_HANDLE_INVALID;
            const Swapchain& sc = *it->second;
            const long lit = rt->endedFrames % 30 == 0 ? litPixels(sc, 2) : -1;
            char text[160];
            std::snprintf(text, sizeof text, " quad %dx%d size %.3fx%.3f released %d lit %ld",
                          q->subImage.imageRect.extent.width, q->subImage.imageRect.extent.height,
                          double(q->size.width), double(q->size.height), sc.releasedThisFrame, lit);
            what += text;
            continue;
        }
        if (l->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
            what += " layer other";
            continue;
        }
        const auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(l);
        what += " projection views " + std::to_string(p->viewCount);
        for (uint32_t v = 0; v < p->viewCount; ++v) {
            const XrSwapchain s = p->views[v].subImage.swapchain;
            auto it = rt->swapchains.find(s);
            if (it == rt->swapchains.end()) return XR_ERROR_HANDLE_INVALID;
            const Swapchain& sc = *it->second;
            // Only every 30th frame is read back: a texture read is a GPU sync.
            const long lit = rt->endedFrames % 30 == 0 ? litPixels(sc, int(v)) : -1;
            what += " eye" + std::to_string(v) + " released " +
                    std::to_string(sc.releasedThisFrame) + " rect " +
                    std::to_string(p->views[v].subImage.imageRect.extent.width) + "x" +
                    std::to_string(p->views[v].subImage.imageRect.extent.height) + " lit " +
                    std::to_string(lit);
        }
    }
    logLine("frame %lld layers %u%s", (long long)rt->frame, info->layerCount, what.c_str());
    ++rt->endedFrames;
    if (rt->endedFrames == 1 && rt->sessionRunning && !rt->focusedSent) {
        rt->focusedSent = true;
        queue(XR_SESSION_STATE_SYNCHRONIZED);
        queue(XR_SESSION_STATE_VISIBLE);
        queue(XR_SESSION_STATE_FOCUSED);
    }
    return XR_SUCCESS;
}

XrResult XRAPI_CALL locateViews(XrSession, const XrViewLocateInfo* info, XrViewState* state,
                                uint32_t capacity, uint32_t* count, XrView* views) {
    *count = 2;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 2) return XR_ERROR_SIZE_INSUFFICIENT;
    Pose base;
    poseInLocal(info->space, info->displayTime, base);
    const Pose head = poseAt("head", frameAt(info->displayTime));
    const glm::dquat bi = glm::inverse(base.q);
    for (int e = 0; e < 2; ++e) {
        Pose eye{head.p + head.q * glm::dvec3(e == 0 ? -0.032 : 0.032, 0, 0), head.q};
        views[e].pose = toXr(Pose{bi * (eye.p - base.p), bi * eye.q});
        views[e].fov = {-0.7f, 0.7f, 0.7f, -0.7f};
    }
    state->viewStateFlags = XR_VIEW_STATE_POSITION_VALID_BIT | XR_VIEW_STATE_ORIENTATION_VALID_BIT |
                            XR_VIEW_STATE_POSITION_TRACKED_BIT |
                            XR_VIEW_STATE_ORIENTATION_TRACKED_BIT;
    return XR_SUCCESS;
}

// ---- actions -----------------------------------------------------------------------------

XrResult XRAPI_CALL createActionSet(XrInstance, const XrActionSetCreateInfo*, XrActionSet* set) {
    static int tags[16];
    *set = reinterpret_cast<XrActionSet>(&tags[rt->actionSets.size() % 16]);
    rt->actionSets.insert(*set);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL destroyActionSet(XrActionSet set) {
    rt->actionSets.erase(set);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL createAction(XrActionSet, const XrActionCreateInfo* info, XrAction* action) {
    auto a = std::make_unique<Action>();
    a->name = info->actionName;
    a->type = info->actionType;
    *action = reinterpret_cast<XrAction>(a.get());
    rt->actions[*action] = std::move(a);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL destroyAction(XrAction action) {
    rt->actions.erase(action);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL suggestBindings(XrInstance, const XrInteractionProfileSuggestedBinding* s) {
    auto& perAction = rt->bindings[s->interactionProfile];
    perAction.clear();
    for (uint32_t i = 0; i < s->countSuggestedBindings; ++i)
        perAction[s->suggestedBindings[i].action].push_back(s->suggestedBindings[i].binding);
    logLine("bindings %s %u", rt->paths[s->interactionProfile].c_str(), s->countSuggestedBindings);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL attachActionSets(XrSession, const XrSessionActionSetsAttachInfo*) {
    for (auto& [h, a] : rt->actions)
        rt->attachedActions.insert(h);
    logLine("attached %zu actions", rt->attachedActions.size());
    return XR_SUCCESS;
}

XrResult XRAPI_CALL getCurrentProfile(XrSession, XrPath, XrInteractionProfileState* state) {
    state->interactionProfile = pathOf(rt->profile);
    return XR_SUCCESS;
}

// Several inputs bound to one float action: the one of largest magnitude wins (as the OpenXR
// spec combines them), so a thumbstick pushed to -1 reads -1.
double actionValue(XrAction action) {
    double v = 0;
    for (const std::string& p : boundInputs(action)) {
        const double x = inputAt(p, rt->frame);
        if (std::abs(x) > std::abs(v)) v = x;
    }
    return v;
}

XrResult XRAPI_CALL syncActions(XrSession, const XrActionsSyncInfo*) {
    for (auto& [h, a] : rt->actions) {
        const double v = actionValue(h);
        if (a->type == XR_ACTION_TYPE_BOOLEAN_INPUT) {
            const bool b = v > 0.5;
            a->changed = b != a->lastBool;
            a->lastBool = b;
        } else if (a->type == XR_ACTION_TYPE_FLOAT_INPUT) {
            a->changed = float(v) != a->lastFloat;
            a->lastFloat = float(v);
        }
    }
    return XR_SUCCESS;
}

XrResult XRAPI_CALL stateBoolean(XrSession, const XrActionStateGetInfo* info,
                                 XrActionStateBoolean* s) {
    const Action& a = *rt->actions.at(info->action);
    s->isActive = boundInputs(info->action).empty() ? XR_FALSE : XR_TRUE;
    s->currentState = a.lastBool ? XR_TRUE : XR_FALSE;
    s->changedSinceLastSync = a.changed ? XR_TRUE : XR_FALSE;
    s->lastChangeTime = kStartNs + (rt->frame + 1) * kPeriodNs;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL stateFloat(XrSession, const XrActionStateGetInfo* info, XrActionStateFloat* s) {
    const Action& a = *rt->actions.at(info->action);
    s->isActive = boundInputs(info->action).empty() ? XR_FALSE : XR_TRUE;
    s->currentState = a.lastFloat;
    s->changedSinceLastSync = a.changed ? XR_TRUE : XR_FALSE;
    s->lastChangeTime = kStartNs + (rt->frame + 1) * kPeriodNs;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL statePose(XrSession, const XrActionStateGetInfo* info, XrActionStatePose* s) {
    s->isActive = handOf(info->action).empty() ? XR_FALSE : XR_TRUE;
    return XR_SUCCESS;
}

XrResult XRAPI_CALL applyHaptic(XrSession, const XrHapticActionInfo* info,
                                const XrHapticBaseHeader* h) {
    const auto* v = reinterpret_cast<const XrHapticVibration*>(h);
    ++rt->hapticCalls;
    logLine("haptic frame %lld hand %s amplitude %.3f duration_ms %.1f", (long long)rt->frame,
            handOf(info->action).c_str(), double(v->amplitude), double(v->duration) / 1e6);
    return XR_SUCCESS;
}

XrResult XRAPI_CALL stopHaptic(XrSession, const XrHapticActionInfo* info) {
    logLine("haptic_stop frame %lld hand %s", (long long)rt->frame, handOf(info->action).c_str());
    return XR_SUCCESS;
}

XrResult XRAPI_CALL getInstanceProcAddr(XrInstance instance, const char* name,
                                        PFN_xrVoidFunction* fn);

struct Entry {
    const char* name;
    PFN_xrVoidFunction fn;
};
#define VSCULPT_ENTRY(api, impl) \
    { #api, reinterpret_cast < PFN_xrVoidFunction>(impl) }
const Entry kEntries[] = {
    VSCULPT_ENTRY(xrGetInstanceProcAddr, getInstanceProcAddr),
    VSCULPT_ENTRY(xrEnumerateInstanceExtensionProperties, enumerateExtensions),
    VSCULPT_ENTRY(xrCreateInstance, createInstance),
    VSCULPT_ENTRY(xrDestroyInstance, destroyInstance),
    VSCULPT_ENTRY(xrGetInstanceProperties, getInstanceProperties),
    VSCULPT_ENTRY(xrResultToString, resultToString),
    VSCULPT_ENTRY(xrStructureTypeToString, structureTypeToString),
    VSCULPT_ENTRY(xrPollEvent, pollEvent),
    VSCULPT_ENTRY(xrGetSystem, getSystem),
    VSCULPT_ENTRY(xrGetSystemProperties, getSystemProperties),
    VSCULPT_ENTRY(xrEnumerateViewConfigurations, enumerateViewConfigurations),
    VSCULPT_ENTRY(xrGetViewConfigurationProperties, getViewConfigurationProperties),
    VSCULPT_ENTRY(xrEnumerateViewConfigurationViews, enumerateViewConfigurationViews),
    VSCULPT_ENTRY(xrEnumerateEnvironmentBlendModes, enumerateBlendModes),
    VSCULPT_ENTRY(xrGetOpenGLGraphicsRequirementsKHR, glRequirements),
    VSCULPT_ENTRY(xrStringToPath, stringToPath),
    VSCULPT_ENTRY(xrPathToString, pathToString),
    VSCULPT_ENTRY(xrCreateSession, createSession),
    VSCULPT_ENTRY(xrDestroySession, destroySession),
    VSCULPT_ENTRY(xrBeginSession, beginSession),
    VSCULPT_ENTRY(xrEndSession, endSession),
    VSCULPT_ENTRY(xrRequestExitSession, requestExitSession),
    VSCULPT_ENTRY(xrEnumerateReferenceSpaces, enumerateReferenceSpaces),
    VSCULPT_ENTRY(xrCreateReferenceSpace, createReferenceSpace),
    VSCULPT_ENTRY(xrCreateActionSpace, createActionSpace),
    VSCULPT_ENTRY(xrDestroySpace, destroySpace),
    VSCULPT_ENTRY(xrLocateSpace, locateSpace),
    VSCULPT_ENTRY(xrEnumerateSwapchainFormats, enumerateSwapchainFormats),
    VSCULPT_ENTRY(xrCreateSwapchain, createSwapchain),
    VSCULPT_ENTRY(xrDestroySwapchain, destroySwapchain),
    VSCULPT_ENTRY(xrEnumerateSwapchainImages, enumerateSwapchainImages),
    VSCULPT_ENTRY(xrAcquireSwapchainImage, acquireImage),
    VSCULPT_ENTRY(xrWaitSwapchainImage, waitImage),
    VSCULPT_ENTRY(xrReleaseSwapchainImage, releaseImage),
    VSCULPT_ENTRY(xrWaitFrame, waitFrame),
    VSCULPT_ENTRY(xrBeginFrame, beginFrame),
    VSCULPT_ENTRY(xrEndFrame, endFrame),
    VSCULPT_ENTRY(xrLocateViews, locateViews),
    VSCULPT_ENTRY(xrCreateActionSet, createActionSet),
    VSCULPT_ENTRY(xrDestroyActionSet, destroyActionSet),
    VSCULPT_ENTRY(xrCreateAction, createAction),
    VSCULPT_ENTRY(xrDestroyAction, destroyAction),
    VSCULPT_ENTRY(xrSuggestInteractionProfileBindings, suggestBindings),
    VSCULPT_ENTRY(xrAttachSessionActionSets, attachActionSets),
    VSCULPT_ENTRY(xrGetCurrentInteractionProfile, getCurrentProfile),
    VSCULPT_ENTRY(xrSyncActions, syncActions),
    VSCULPT_ENTRY(xrGetActionStateBoolean, stateBoolean),
    VSCULPT_ENTRY(xrGetActionStateFloat, stateFloat),
    VSCULPT_ENTRY(xrGetActionStatePose, statePose),
    VSCULPT_ENTRY(xrApplyHapticFeedback, applyHaptic),
    VSCULPT_ENTRY(xrStopHapticFeedback, stopHaptic),
};
#undef VSCULPT_ENTRY

XrResult XRAPI_CALL getInstanceProcAddr(XrInstance, const char* name, PFN_xrVoidFunction* fn) {
    for (const Entry& e : kEntries)
        if (std::strcmp(e.name, name) == 0) {
            *fn = e.fn;
            return XR_SUCCESS;
        }
    *fn = nullptr;
    return XR_ERROR_FUNCTION_UNSUPPORTED;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) XrResult XRAPI_CALL
xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo* loader,
                                  XrNegotiateRuntimeRequest* request) {
    if (!loader || loader->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO || !request ||
        request->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
        loader->minInterfaceVersion > 1 || loader->maxInterfaceVersion < 1)
        return XR_ERROR_INITIALIZATION_FAILED;
    request->runtimeInterfaceVersion = 1;
    request->runtimeApiVersion = XR_CURRENT_API_VERSION;
    request->getInstanceProcAddr = getInstanceProcAddr;
    return XR_SUCCESS;
}
