// SPDX-License-Identifier: MIT
#include "vsculpt/devices/XrHeadset.h"

#include "vsculpt/devices/XrBindings.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <vector>

// openxr_platform.h needs the Xlib and GLX types for the OpenGL/Xlib graphics binding. X11's
// macros (None, Bool, Status) come last and are not used below.
#define XR_USE_PLATFORM_XLIB
#define XR_USE_GRAPHICS_API_OPENGL
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
#include <openxr/openxr_reflection.h>

// OpenXR's structures are filled the C way, `XrFoo foo{XR_TYPE_FOO}`: the type tag set, the
// rest zero. That is the point, not an oversight.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace vsculpt::devices {

const char* toString(XrState s) {
    switch (s) {
        case XrState::Unknown:
            return "unknown";
        case XrState::Idle:
            return "idle";
        case XrState::Ready:
            return "ready";
        case XrState::Synchronized:
            return "synchronized";
        case XrState::Visible:
            return "visible";
        case XrState::Focused:
            return "focused";
        case XrState::Stopping:
            return "stopping";
        case XrState::LossPending:
            return "loss pending";
        case XrState::Exiting:
            return "exiting";
    }
    return "?";
}

namespace {

// GL internal formats the swapchain may offer (GL/gl.h has the first only on some systems).
constexpr int64_t kGlRgba8 = 0x8058, kGlSrgb8Alpha8 = 0x8C43;

std::string resultName(XrInstance instance, XrResult r) {
    char text[XR_MAX_RESULT_STRING_SIZE] = {};
    if (instance != XR_NULL_HANDLE && XR_SUCCEEDED(xrResultToString(instance, r, text)))
        return text;
    // No instance (the loader found no runtime): the headers' own table names it.
    switch (r) {
#define VSCULPT_XR_RESULT_CASE(name, value) \
    case name:                              \
        return #name;
        XR_LIST_ENUM_XrResult(VSCULPT_XR_RESULT_CASE)
#undef VSCULPT_XR_RESULT_CASE
            default : break;
    }
    return "XrResult " + std::to_string(int(r));
}

/// Owns one OpenXR handle; destroyed with its xrDestroy* function.
template <typename H, XrResult (*Destroy)(H)>
class Handle {
  public:
    Handle() = default;
    ~Handle() { reset(); }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    H get() const { return mH; }
    /// For the xrCreate* out parameter: frees what was held first.
    H* put() {
        reset();
        return &mH;
    }
    void reset() {
        if (mH != XR_NULL_HANDLE) Destroy(mH);
        mH = XR_NULL_HANDLE;
    }
    explicit operator bool() const { return mH != XR_NULL_HANDLE; }

  private:
    H mH = XR_NULL_HANDLE;
};

XrState stateOf(XrSessionState s) {
    switch (s) {
        case XR_SESSION_STATE_IDLE:
            return XrState::Idle;
        case XR_SESSION_STATE_READY:
            return XrState::Ready;
        case XR_SESSION_STATE_SYNCHRONIZED:
            return XrState::Synchronized;
        case XR_SESSION_STATE_VISIBLE:
            return XrState::Visible;
        case XR_SESSION_STATE_FOCUSED:
            return XrState::Focused;
        case XR_SESSION_STATE_STOPPING:
            return XrState::Stopping;
        case XR_SESSION_STATE_LOSS_PENDING:
            return XrState::LossPending;
        case XR_SESSION_STATE_EXITING:
            return XrState::Exiting;
        default:
            return XrState::Unknown;
    }
}

glm::dmat4 matrixOf(const XrPosef& p) {
    return matrixFromXrPose(
        glm::dvec3(p.position.x, p.position.y, p.position.z),
        glm::dquat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z));
}

XrBool32 XRAPI_CALL onDebugMessage(XrDebugUtilsMessageSeverityFlagsEXT severity,
                                   XrDebugUtilsMessageTypeFlagsEXT,
                                   const XrDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    const bool bad = (severity & (XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                  XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)) != 0;
    const char* fn = data && data->functionName ? data->functionName : "";
    const char* msg = data && data->message ? data->message : "";
    if (bad) {
        ++*static_cast<size_t*>(user);
        spdlog::warn("openxr: {}: {}", fn, msg);
    } else {
        spdlog::debug("openxr: {}: {}", fn, msg);
    }
    return XR_FALSE;
}

}  // namespace

struct XrHeadset::Impl {
    Handle<XrInstance, xrDestroyInstance> instance;
    XrDebugUtilsMessengerEXT messenger = XR_NULL_HANDLE;
    PFN_xrDestroyDebugUtilsMessengerEXT destroyMessenger = nullptr;
    XrSystemId system = XR_NULL_SYSTEM_ID;
    XrGraphicsRequirementsOpenGLKHR glRequirements{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
    std::string runtime, systemName;
    Handle<XrSession, xrDestroySession> session;
    Handle<XrSpace, xrDestroySpace> local, view, penSpace, mouseSpace;
    struct Eye {
        Handle<XrSwapchain, xrDestroySwapchain> swapchain;
        std::vector<XrSwapchainImageOpenGLKHR> images;
        int width = 0, height = 0;
    };
    std::array<Eye, 2> eyes;
    Eye panel;
    XrPanel panelPlace;
    std::array<XrView, 2> views{{{XR_TYPE_VIEW}, {XR_TYPE_VIEW}}};
    Handle<XrActionSet, xrDestroyActionSet> actionSet;
    std::array<XrAction, kXrActionCount> actions{};  // destroyed with the set
    XrEnvironmentBlendMode blend = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    int64_t format = 0;  // the swapchains' GL internal format
    XrState state = XrState::Unknown;
    bool running = false, exitRequested = false;
    size_t debugMessages = 0;
    uint64_t frames = 0;

    void check(XrResult r, const char* call) const {
        if (XR_FAILED(r)) throw XrFailure(std::string(call) + ": " + resultName(instance.get(), r));
    }
    XrAction action(XrActionId id) const { return actions[size_t(id)]; }
    XrPath path(const std::string& p) const {
        XrPath out = XR_NULL_PATH;
        check(xrStringToPath(instance.get(), p.c_str(), &out), "xrStringToPath");
        return out;
    }

    ~Impl() {
        // Children before their parents: spaces and swapchains, the actions, the session,
        // then the instance (members would go in reverse declaration order, not this one).
        penSpace.reset();
        mouseSpace.reset();
        local.reset();
        view.reset();
        for (Eye& e : eyes)
            e.swapchain.reset();
        panel.swapchain.reset();
        actionSet.reset();
        session.reset();
        if (messenger != XR_NULL_HANDLE && destroyMessenger) destroyMessenger(messenger);
        instance.reset();
    }
};

XrHeadset::XrHeadset(const Options& options) : mImpl(std::make_unique<Impl>()) {
    Impl& m = *mImpl;
    // The loader prints its own "Error [GENERAL | ...]" lines to stderr before this says, in
    // one line, what is missing and what to do; XR_LOADER_DEBUG=error (or all) brings them back.
    ::setenv("XR_LOADER_DEBUG", "none", /*overwrite=*/0);
    uint32_t count = 0;
    XrResult r = xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr);
    if (XR_FAILED(r))
        throw XrUnavailable("no OpenXR runtime (" + resultName(XR_NULL_HANDLE, r) +
                            "): install and start one (Monado, SteamVR), or point "
                            "XR_RUNTIME_JSON at its manifest");
    std::vector<XrExtensionProperties> extensions(count, {XR_TYPE_EXTENSION_PROPERTIES});
    xrEnumerateInstanceExtensionProperties(nullptr, count, &count, extensions.data());
    bool gl = false, debugUtils = false;
    for (const auto& e : extensions) {
        gl = gl || std::strcmp(e.extensionName, XR_KHR_OPENGL_ENABLE_EXTENSION_NAME) == 0;
        debugUtils =
            debugUtils || std::strcmp(e.extensionName, XR_EXT_DEBUG_UTILS_EXTENSION_NAME) == 0;
    }
    if (!gl) throw XrUnavailable("the OpenXR runtime does not offer XR_KHR_opengl_enable");
    std::vector<const char*> enable = {XR_KHR_OPENGL_ENABLE_EXTENSION_NAME};
    const bool messenger = options.debugMessenger && debugUtils;
    if (messenger) enable.push_back(XR_EXT_DEBUG_UTILS_EXTENSION_NAME);

    XrInstanceCreateInfo ci{XR_TYPE_INSTANCE_CREATE_INFO};
    std::strncpy(ci.applicationInfo.applicationName, options.applicationName.c_str(),
                 XR_MAX_APPLICATION_NAME_SIZE - 1);
    std::strncpy(ci.applicationInfo.engineName, "vsculpt", XR_MAX_ENGINE_NAME_SIZE - 1);
    ci.applicationInfo.applicationVersion = 1;
    ci.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
    ci.enabledExtensionCount = uint32_t(enable.size());
    ci.enabledExtensionNames = enable.data();
    r = xrCreateInstance(&ci, m.instance.put());
    if (XR_FAILED(r))
        throw XrUnavailable("the OpenXR runtime refused an instance (" +
                            resultName(XR_NULL_HANDLE, r) + ")");

    if (messenger) {
        PFN_xrCreateDebugUtilsMessengerEXT create = nullptr;
        xrGetInstanceProcAddr(m.instance.get(), "xrCreateDebugUtilsMessengerEXT",
                              reinterpret_cast<PFN_xrVoidFunction*>(&create));
        xrGetInstanceProcAddr(m.instance.get(), "xrDestroyDebugUtilsMessengerEXT",
                              reinterpret_cast<PFN_xrVoidFunction*>(&m.destroyMessenger));
        if (create && m.destroyMessenger) {
            XrDebugUtilsMessengerCreateInfoEXT di{XR_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            di.messageSeverities = XR_DEBUG_UTILS_MESSAGE_SEVERITY_VERBOSE_BIT_EXT |
                                   XR_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT |
                                   XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            di.messageTypes = XR_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                              XR_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                              XR_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                              XR_DEBUG_UTILS_MESSAGE_TYPE_CONFORMANCE_BIT_EXT;
            di.userCallback = onDebugMessage;
            di.userData = &m.debugMessages;
            m.check(create(m.instance.get(), &di, &m.messenger), "xrCreateDebugUtilsMessengerEXT");
        }
    }

    XrInstanceProperties ip{XR_TYPE_INSTANCE_PROPERTIES};
    m.check(xrGetInstanceProperties(m.instance.get(), &ip), "xrGetInstanceProperties");
    m.runtime = std::string(ip.runtimeName) + " " +
                std::to_string(XR_VERSION_MAJOR(ip.runtimeVersion)) + "." +
                std::to_string(XR_VERSION_MINOR(ip.runtimeVersion)) + "." +
                std::to_string(XR_VERSION_PATCH(ip.runtimeVersion));

    XrSystemGetInfo si{XR_TYPE_SYSTEM_GET_INFO};
    si.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    r = xrGetSystem(m.instance.get(), &si, &m.system);
    if (XR_FAILED(r))
        throw XrUnavailable("no headset (" + resultName(m.instance.get(), r) + " from " +
                            m.runtime + "): connect and switch on the headset");
    XrSystemProperties sp{XR_TYPE_SYSTEM_PROPERTIES};
    m.check(xrGetSystemProperties(m.instance.get(), m.system, &sp), "xrGetSystemProperties");
    m.systemName = sp.systemName;

    // The spec wants the graphics requirements queried before the session is created.
    PFN_xrGetOpenGLGraphicsRequirementsKHR requirements = nullptr;
    m.check(xrGetInstanceProcAddr(m.instance.get(), "xrGetOpenGLGraphicsRequirementsKHR",
                                  reinterpret_cast<PFN_xrVoidFunction*>(&requirements)),
            "xrGetInstanceProcAddr(xrGetOpenGLGraphicsRequirementsKHR)");
    m.check(requirements(m.instance.get(), m.system, &m.glRequirements),
            "xrGetOpenGLGraphicsRequirementsKHR");
}

XrHeadset::~XrHeadset() = default;

std::string XrHeadset::runtimeName() const {
    return mImpl->runtime;
}

std::string XrHeadset::systemName() const {
    return mImpl->systemName;
}

std::string XrHeadset::glRequirements() const {
    const auto v = [](XrVersion x) {
        return std::to_string(XR_VERSION_MAJOR(x)) + "." + std::to_string(XR_VERSION_MINOR(x));
    };
    return v(mImpl->glRequirements.minApiVersionSupported) + "-" +
           v(mImpl->glRequirements.maxApiVersionSupported);
}

void XrHeadset::startSession(const GlxBinding& gl) {
    Impl& m = *mImpl;
    // The viewer's context is OpenGL 3.3 core.
    if (m.glRequirements.minApiVersionSupported > XR_MAKE_VERSION(3, 3, 0))
        throw XrFailure("the OpenXR runtime needs OpenGL " + glRequirements() +
                        "; vsculpt's context is 3.3");
    XrGraphicsBindingOpenGLXlibKHR binding{XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR};
    binding.xDisplay = static_cast<Display*>(gl.display);
    binding.visualid = gl.visualId;
    binding.glxFBConfig = static_cast<GLXFBConfig>(gl.fbConfig);
    binding.glxDrawable = gl.drawable;
    binding.glxContext = static_cast<GLXContext>(gl.context);
    XrSessionCreateInfo sci{XR_TYPE_SESSION_CREATE_INFO};
    sci.next = &binding;
    sci.systemId = m.system;
    m.check(xrCreateSession(m.instance.get(), &sci, m.session.put()), "xrCreateSession");

    XrReferenceSpaceCreateInfo rs{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    rs.poseInReferenceSpace.orientation.w = 1;
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    m.check(xrCreateReferenceSpace(m.session.get(), &rs, m.local.put()), "xrCreateReferenceSpace");
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    m.check(xrCreateReferenceSpace(m.session.get(), &rs, m.view.put()), "xrCreateReferenceSpace");

    uint32_t n = 0;
    m.check(
        xrEnumerateEnvironmentBlendModes(m.instance.get(), m.system,
                                         XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &n, nullptr),
        "xrEnumerateEnvironmentBlendModes");
    std::vector<XrEnvironmentBlendMode> blends(n);
    m.check(xrEnumerateEnvironmentBlendModes(m.instance.get(), m.system,
                                             XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, n, &n,
                                             blends.data()),
            "xrEnumerateEnvironmentBlendModes");
    if (!blends.empty()) m.blend = blends[0];

    m.check(
        xrEnumerateViewConfigurationViews(
            m.instance.get(), m.system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &n, nullptr),
        "xrEnumerateViewConfigurationViews");
    if (n != 2) throw XrFailure("the headset has " + std::to_string(n) + " views, not 2");
    std::vector<XrViewConfigurationView> configViews(n, {XR_TYPE_VIEW_CONFIGURATION_VIEW});
    m.check(xrEnumerateViewConfigurationViews(m.instance.get(), m.system,
                                              XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, n, &n,
                                              configViews.data()),
            "xrEnumerateViewConfigurationViews");

    m.check(xrEnumerateSwapchainFormats(m.session.get(), 0, &n, nullptr),
            "xrEnumerateSwapchainFormats");
    std::vector<int64_t> formats(n);
    m.check(xrEnumerateSwapchainFormats(m.session.get(), n, &n, formats.data()),
            "xrEnumerateSwapchainFormats");
    // Linear RGBA8 shows the clay as the desktop window does; sRGB is the fallback.
    int64_t format = 0;
    for (int64_t want : {kGlRgba8, kGlSrgb8Alpha8})
        for (int64_t f : formats)
            if (f == want && format == 0) format = f;
    if (format == 0) throw XrFailure("the runtime offers no RGBA8 swapchain format");
    m.format = format;
    for (int e = 0; e < 2; ++e) {
        Impl::Eye& eye = m.eyes[size_t(e)];
        XrSwapchainCreateInfo sc{XR_TYPE_SWAPCHAIN_CREATE_INFO};
        sc.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
        sc.format = format;
        sc.sampleCount = 1;
        sc.width = configViews[size_t(e)].recommendedImageRectWidth;
        sc.height = configViews[size_t(e)].recommendedImageRectHeight;
        sc.faceCount = 1;
        sc.arraySize = 1;
        sc.mipCount = 1;
        m.check(xrCreateSwapchain(m.session.get(), &sc, eye.swapchain.put()), "xrCreateSwapchain");
        eye.width = int(sc.width);
        eye.height = int(sc.height);
        m.check(xrEnumerateSwapchainImages(eye.swapchain.get(), 0, &n, nullptr),
                "xrEnumerateSwapchainImages");
        eye.images.assign(n, {XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR});
        m.check(xrEnumerateSwapchainImages(
                    eye.swapchain.get(), n, &n,
                    reinterpret_cast<XrSwapchainImageBaseHeader*>(eye.images.data())),
                "xrEnumerateSwapchainImages");
    }

    XrActionSetCreateInfo as{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(as.actionSetName, "sculpting");
    std::strcpy(as.localizedActionSetName, "Sculpting");
    m.check(xrCreateActionSet(m.instance.get(), &as, m.actionSet.put()), "xrCreateActionSet");
    for (int i = 0; i < kXrActionCount; ++i) {
        const auto id = XrActionId(i);
        XrActionCreateInfo ac{XR_TYPE_ACTION_CREATE_INFO};
        std::strncpy(ac.actionName, xrActionName(id), XR_MAX_ACTION_NAME_SIZE - 1);
        std::strncpy(ac.localizedActionName, xrActionName(id),
                     XR_MAX_LOCALIZED_ACTION_NAME_SIZE - 1);
        switch (xrActionKind(id)) {
            case XrActionKind::Pose:
                ac.actionType = XR_ACTION_TYPE_POSE_INPUT;
                break;
            case XrActionKind::Float:
                ac.actionType = XR_ACTION_TYPE_FLOAT_INPUT;
                break;
            case XrActionKind::Boolean:
                ac.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
                break;
            case XrActionKind::Vibration:
                ac.actionType = XR_ACTION_TYPE_VIBRATION_OUTPUT;
                break;
        }
        m.check(xrCreateAction(m.actionSet.get(), &ac, &m.actions[size_t(i)]), "xrCreateAction");
    }
    for (const XrProfileBindings& p : xrSuggestedBindings()) {
        std::vector<XrActionSuggestedBinding> b;
        for (const XrSuggestedBinding& s : p.bindings)
            b.push_back({m.action(s.action), m.path(s.path)});
        XrInteractionProfileSuggestedBinding sb{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
        sb.interactionProfile = m.path(p.profile);
        sb.countSuggestedBindings = uint32_t(b.size());
        sb.suggestedBindings = b.data();
        // A runtime that does not know a profile refuses it; the others still apply.
        const XrResult sr = xrSuggestInteractionProfileBindings(m.instance.get(), &sb);
        if (XR_FAILED(sr))
            spdlog::warn("openxr: bindings for {} refused: {}", p.profile,
                         resultName(m.instance.get(), sr));
    }
    XrActionSpaceCreateInfo asi{XR_TYPE_ACTION_SPACE_CREATE_INFO};
    asi.poseInActionSpace.orientation.w = 1;
    asi.action = m.action(XrActionId::PenPose);
    m.check(xrCreateActionSpace(m.session.get(), &asi, m.penSpace.put()), "xrCreateActionSpace");
    asi.action = m.action(XrActionId::MousePose);
    m.check(xrCreateActionSpace(m.session.get(), &asi, m.mouseSpace.put()), "xrCreateActionSpace");
    XrSessionActionSetsAttachInfo at{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    const XrActionSet set = m.actionSet.get();
    at.countActionSets = 1;
    at.actionSets = &set;
    m.check(xrAttachSessionActionSets(m.session.get(), &at), "xrAttachSessionActionSets");
}

bool XrHeadset::pollEvents(std::string& why) {
    Impl& m = *mImpl;
    for (;;) {
        XrEventDataBuffer ev{XR_TYPE_EVENT_DATA_BUFFER};
        const XrResult r = xrPollEvent(m.instance.get(), &ev);
        m.check(r, "xrPollEvent");
        if (r == XR_EVENT_UNAVAILABLE) break;
        if (ev.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING) {
            why = "the OpenXR runtime is going away (instance loss pending)";
            return false;
        }
        if (ev.type == XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED && m.session) {
            XrInteractionProfileState ps{XR_TYPE_INTERACTION_PROFILE_STATE};
            if (XR_SUCCEEDED(xrGetCurrentInteractionProfile(m.session.get(),
                                                            m.path("/user/hand/right"), &ps)) &&
                ps.interactionProfile != XR_NULL_PATH) {
                char text[XR_MAX_PATH_LENGTH] = {};
                uint32_t len = 0;
                xrPathToString(m.instance.get(), ps.interactionProfile, sizeof text, &len, text);
                spdlog::info("openxr: controllers: {}", text);
            }
            continue;
        }
        if (ev.type != XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) continue;
        const auto& sc = reinterpret_cast<const XrEventDataSessionStateChanged&>(ev);
        m.state = stateOf(sc.state);
        spdlog::debug("openxr: session {}", toString(m.state));
        switch (m.state) {
            case XrState::Ready: {
                XrSessionBeginInfo bi{XR_TYPE_SESSION_BEGIN_INFO};
                bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
                m.check(xrBeginSession(m.session.get(), &bi), "xrBeginSession");
                m.running = true;
                break;
            }
            case XrState::Stopping:
                m.check(xrEndSession(m.session.get()), "xrEndSession");
                m.running = false;
                break;
            case XrState::Exiting:
                why = m.exitRequested ? "session ended" : "the OpenXR runtime ended the session";
                return false;
            case XrState::LossPending:
                why = "the headset was lost (session loss pending)";
                return false;
            default:
                break;
        }
    }
    // Asked to stop before the session ever ran: nothing to end.
    if (m.exitRequested && !m.running &&
        (m.state == XrState::Idle || m.state == XrState::Unknown)) {
        why = "session ended";
        return false;
    }
    return true;
}

XrState XrHeadset::state() const {
    return mImpl->state;
}

bool XrHeadset::running() const {
    return mImpl->running;
}

bool XrHeadset::focused() const {
    return mImpl->state == XrState::Focused;
}

void XrHeadset::requestExit() {
    Impl& m = *mImpl;
    if (m.exitRequested) return;
    m.exitRequested = true;
    if (m.running) m.check(xrRequestExitSession(m.session.get()), "xrRequestExitSession");
}

XrFrameTiming XrHeadset::waitFrame() {
    Impl& m = *mImpl;
    XrFrameWaitInfo wi{XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    m.check(xrWaitFrame(m.session.get(), &wi, &fs), "xrWaitFrame");
    return {fs.predictedDisplayTime, fs.predictedDisplayPeriod, fs.shouldRender == XR_TRUE};
}

void XrHeadset::beginFrame() {
    XrFrameBeginInfo bi{XR_TYPE_FRAME_BEGIN_INFO};
    mImpl->check(xrBeginFrame(mImpl->session.get(), &bi), "xrBeginFrame");
}

XrControllers XrHeadset::syncInput(int64_t time) {
    Impl& m = *mImpl;
    XrControllers c;
    if (!focused()) return c;
    XrActiveActionSet active{m.actionSet.get(), XR_NULL_PATH};
    XrActionsSyncInfo si{XR_TYPE_ACTIONS_SYNC_INFO};
    si.countActiveActionSets = 1;
    si.activeActionSets = &active;
    m.check(xrSyncActions(m.session.get(), &si), "xrSyncActions");
    XrActionStateGetInfo gi{XR_TYPE_ACTION_STATE_GET_INFO};
    gi.action = m.action(XrActionId::PenTrigger);
    XrActionStateFloat f{XR_TYPE_ACTION_STATE_FLOAT};
    m.check(xrGetActionStateFloat(m.session.get(), &gi, &f), "xrGetActionStateFloat");
    if (f.isActive) c.trigger = f.currentState;
    auto boolean = [&](XrActionId id, bool edge) {
        gi.action = m.action(id);
        XrActionStateBoolean b{XR_TYPE_ACTION_STATE_BOOLEAN};
        m.check(xrGetActionStateBoolean(m.session.get(), &gi, &b), "xrGetActionStateBoolean");
        if (!b.isActive) return false;
        return b.currentState == XR_TRUE && (!edge || b.changedSinceLastSync == XR_TRUE);
    };
    auto analog = [&](XrActionId id) {
        gi.action = m.action(id);
        XrActionStateFloat a{XR_TYPE_ACTION_STATE_FLOAT};
        m.check(xrGetActionStateFloat(m.session.get(), &gi, &a), "xrGetActionStateFloat");
        return a.isActive ? a.currentState : 0.0f;
    };
    c.penStickX = analog(XrActionId::PenStickX);
    c.penStickY = analog(XrActionId::PenStickY);
    c.mouseStickY = analog(XrActionId::MouseStickY);
    c.grip = boolean(XrActionId::MouseGrip, false);
    c.undo = boolean(XrActionId::Undo, true);
    c.cycleTool = boolean(XrActionId::CycleTool, true);
    c.step = boolean(XrActionId::Step, true);
    c.overview = boolean(XrActionId::Overview, true);
    auto pose = [&](XrActionId id, XrSpace space) -> std::optional<glm::dmat4> {
        gi.action = m.action(id);
        XrActionStatePose ps{XR_TYPE_ACTION_STATE_POSE};
        m.check(xrGetActionStatePose(m.session.get(), &gi, &ps), "xrGetActionStatePose");
        if (!ps.isActive) return std::nullopt;
        XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
        m.check(xrLocateSpace(space, m.local.get(), time, &loc), "xrLocateSpace");
        const XrSpaceLocationFlags need =
            XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT;
        if ((loc.locationFlags & need) != need) return std::nullopt;
        return matrixOf(loc.pose);
    };
    c.localFromPen = pose(XrActionId::PenPose, m.penSpace.get());
    c.localFromMouse = pose(XrActionId::MousePose, m.mouseSpace.get());
    return c;
}

std::array<XrEyeView, 2> XrHeadset::locateEyes(int64_t time) {
    Impl& m = *mImpl;
    XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
    li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    li.displayTime = time;
    li.space = m.local.get();
    XrViewState vs{XR_TYPE_VIEW_STATE};
    uint32_t n = 0;
    m.views = {{{XR_TYPE_VIEW}, {XR_TYPE_VIEW}}};
    m.check(xrLocateViews(m.session.get(), &li, &vs, 2, &n, m.views.data()), "xrLocateViews");
    std::array<XrEyeView, 2> out;
    for (size_t e = 0; e < 2; ++e) {
        const XrView& v = m.views[e];
        // Untracked views still get drawn (from the last pose the runtime gave, or the origin).
        if (!(vs.viewStateFlags & XR_VIEW_STATE_ORIENTATION_VALID_BIT))
            m.views[e].pose.orientation = {0, 0, 0, 1};
        out[e].localFromEye = matrixOf(m.views[e].pose);
        out[e].angleLeft = v.fov.angleLeft;
        out[e].angleRight = v.fov.angleRight;
        out[e].angleUp = v.fov.angleUp;
        out[e].angleDown = v.fov.angleDown;
        out[e].width = m.eyes[e].width;
        out[e].height = m.eyes[e].height;
    }
    return out;
}

void XrHeadset::createPanel(const XrPanel& panel) {
    Impl& m = *mImpl;
    m.panelPlace = panel;
    XrSwapchainCreateInfo sc{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    sc.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
    sc.format = m.format;
    sc.sampleCount = 1;
    sc.width = uint32_t(panel.widthPx);
    sc.height = uint32_t(panel.heightPx);
    sc.faceCount = 1;
    sc.arraySize = 1;
    sc.mipCount = 1;
    m.check(xrCreateSwapchain(m.session.get(), &sc, m.panel.swapchain.put()), "xrCreateSwapchain");
    m.panel.width = panel.widthPx;
    m.panel.height = panel.heightPx;
    uint32_t n = 0;
    m.check(xrEnumerateSwapchainImages(m.panel.swapchain.get(), 0, &n, nullptr),
            "xrEnumerateSwapchainImages");
    m.panel.images.assign(n, {XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR});
    m.check(xrEnumerateSwapchainImages(
                m.panel.swapchain.get(), n, &n,
                reinterpret_cast<XrSwapchainImageBaseHeader*>(m.panel.images.data())),
            "xrEnumerateSwapchainImages");
}

unsigned XrHeadset::acquirePanel() {
    Impl& m = *mImpl;
    uint32_t index = 0;
    XrSwapchainImageAcquireInfo ai{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
    m.check(xrAcquireSwapchainImage(m.panel.swapchain.get(), &ai, &index),
            "xrAcquireSwapchainImage");
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    m.check(xrWaitSwapchainImage(m.panel.swapchain.get(), &wi), "xrWaitSwapchainImage");
    return m.panel.images.at(index).image;
}

void XrHeadset::releasePanel() {
    XrSwapchainImageReleaseInfo ri{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
    mImpl->check(xrReleaseSwapchainImage(mImpl->panel.swapchain.get(), &ri),
                 "xrReleaseSwapchainImage");
}

unsigned XrHeadset::acquireEye(int eye) {
    Impl& m = *mImpl;
    Impl::Eye& e = m.eyes[size_t(eye)];
    uint32_t index = 0;
    XrSwapchainImageAcquireInfo ai{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
    m.check(xrAcquireSwapchainImage(e.swapchain.get(), &ai, &index), "xrAcquireSwapchainImage");
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    m.check(xrWaitSwapchainImage(e.swapchain.get(), &wi), "xrWaitSwapchainImage");
    return e.images.at(index).image;
}

void XrHeadset::releaseEye(int eye) {
    XrSwapchainImageReleaseInfo ri{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
    mImpl->check(xrReleaseSwapchainImage(mImpl->eyes[size_t(eye)].swapchain.get(), &ri),
                 "xrReleaseSwapchainImage");
}

void XrHeadset::endFrame(const XrFrameTiming& timing, const std::array<XrEyeView, 2>* eyes,
                         bool panel) {
    Impl& m = *mImpl;
    std::array<XrCompositionLayerProjectionView, 2> pv{};
    XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    XrCompositionLayerQuad quad{XR_TYPE_COMPOSITION_LAYER_QUAD};
    const XrCompositionLayerBaseHeader* layers[2] = {
        reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer),
        reinterpret_cast<const XrCompositionLayerBaseHeader*>(&quad)};
    XrFrameEndInfo ei{XR_TYPE_FRAME_END_INFO};
    ei.displayTime = timing.predictedDisplayTime;
    ei.environmentBlendMode = m.blend;
    if (eyes) {
        for (size_t e = 0; e < 2; ++e) {
            pv[e] = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
            pv[e].pose = m.views[e].pose;
            pv[e].fov = m.views[e].fov;
            pv[e].subImage.swapchain = m.eyes[e].swapchain.get();
            pv[e].subImage.imageRect = {{0, 0}, {m.eyes[e].width, m.eyes[e].height}};
            pv[e].subImage.imageArrayIndex = 0;
        }
        layer.space = m.local.get();
        layer.viewCount = 2;
        layer.views = pv.data();
        ei.layerCount = 1;
        ei.layers = layers;
        if (panel && m.panel.swapchain) {
            const XrPanel& p = m.panelPlace;
            // The panel's image is premultiplied (ImGui over a clear background): blend it.
            quad.layerFlags = XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT;
            quad.space = m.local.get();
            quad.eyeVisibility = XR_EYE_VISIBILITY_BOTH;
            quad.subImage.swapchain = m.panel.swapchain.get();
            quad.subImage.imageRect = {{0, 0}, {m.panel.width, m.panel.height}};
            quad.pose.position = {float(p.positionM.x), float(p.positionM.y), float(p.positionM.z)};
            quad.pose.orientation = {float(p.orientation.x), float(p.orientation.y),
                                     float(p.orientation.z), float(p.orientation.w)};
            quad.size = {float(p.widthM),
                         float(p.widthM * m.panel.height / std::max(1, m.panel.width))};
            ei.layerCount = 2;
        }
    }
    m.check(xrEndFrame(m.session.get(), &ei), "xrEndFrame");
    ++m.frames;
}

void XrHeadset::vibrate(float amplitude, int64_t durationNs) {
    Impl& m = *mImpl;
    XrHapticActionInfo hi{XR_TYPE_HAPTIC_ACTION_INFO};
    hi.action = m.action(XrActionId::PenHaptic);
    XrHapticVibration v{XR_TYPE_HAPTIC_VIBRATION};
    v.amplitude = amplitude;
    v.duration = durationNs > 0 ? durationNs : XR_MIN_HAPTIC_DURATION;
    v.frequency = XR_FREQUENCY_UNSPECIFIED;
    m.check(xrApplyHapticFeedback(m.session.get(), &hi,
                                  reinterpret_cast<const XrHapticBaseHeader*>(&v)),
            "xrApplyHapticFeedback");
}

void XrHeadset::stopVibration() {
    Impl& m = *mImpl;
    XrHapticActionInfo hi{XR_TYPE_HAPTIC_ACTION_INFO};
    hi.action = m.action(XrActionId::PenHaptic);
    m.check(xrStopHapticFeedback(m.session.get(), &hi), "xrStopHapticFeedback");
}

size_t XrHeadset::debugMessages() const {
    return mImpl->debugMessages;
}

uint64_t XrHeadset::framesSubmitted() const {
    return mImpl->frames;
}

}  // namespace vsculpt::devices
