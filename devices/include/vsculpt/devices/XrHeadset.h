// SPDX-License-Identifier: MIT
/// @file XrHeadset.h
/// @brief An OpenXR headset and its controllers (docs/xr.md): instance, system and an OpenGL
/// (Xlib/GLX) session, one swapchain per eye, the action set of XrBindings.h, the session
/// state machine and the xrWaitFrame-paced frame calls. Poses come back in OpenXR's local
/// space (metres); the application maps them into its world.
///
/// Every OpenXR handle is owned here and destroyed in reverse order of creation. Failures
/// throw: XrUnavailable when there is no runtime or no headset (the caller falls back to the
/// desktop window), XrFailure for a call that fails later.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace vsculpt::devices {

/// No OpenXR runtime installed or running, or no headset connected: nothing to show on.
class XrUnavailable : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// An OpenXR call failed during a session (the message names the call and the result).
class XrFailure : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// The application's GLX context, for XrGraphicsBindingOpenGLXlibKHR (opaque pointers so
/// that this header needs neither Xlib nor GLX).
struct GlxBinding {
    void* display = nullptr;  ///< Display*
    uint32_t visualId = 0;
    void* fbConfig = nullptr;  ///< GLXFBConfig
    unsigned long drawable = 0;
    void* context = nullptr;  ///< GLXContext
};

enum class XrState {
    Unknown,
    Idle,
    Ready,
    Synchronized,
    Visible,
    Focused,
    Stopping,
    LossPending,
    Exiting
};
const char* toString(XrState state);

/// One sync of the controllers. Poses are rigid, metres, in local space; nullopt when not
/// tracked. Button fields are true in the sync in which the button went down.
struct XrControllers {
    std::optional<glm::dmat4> localFromPen, localFromMouse;
    float trigger = 0;
    bool grip = false;
    bool undo = false, cycleTool = false, step = false, overview = false;
    float penStickX = 0, penStickY = 0, mouseStickY = 0;  ///< -1..1 (0: not bound)
};

/// One eye of a frame: where it is (local, metres), its field of view (radians) and the GL
/// texture to draw it into (valid between acquireEye and releaseEye).
struct XrEyeView {
    glm::dmat4 localFromEye{1.0};
    double angleLeft = 0, angleRight = 0, angleUp = 0, angleDown = 0;
    int width = 0, height = 0;
    unsigned texture = 0;
};

/// A flat panel in the scene (an OpenXR quad layer): the status and the palette, drawn by the
/// application into its own swapchain image. Local space, metres; the panel faces +z of its
/// orientation. By default at the left, within the pen's reach of a pointing ray, turned
/// to face where the head was at the start (about 37 degrees about +y).
struct XrPanel {
    glm::dvec3 positionM{-0.42, -0.1, -0.55};
    glm::dquat orientation{0.94730349253202, 0, 0.32033746742558, 0};  ///< w, x, y, z
    double widthM = 0.36;
    int widthPx = 720, heightPx = 360;  ///< its image; the height in metres follows
};

struct XrFrameTiming {
    int64_t predictedDisplayTime = 0;  ///< XrTime, ns
    int64_t predictedDisplayPeriod = 0;
    bool shouldRender = false;
};

class XrHeadset {
  public:
    struct Options {
        std::string applicationName = "vsculpt";
        /// Create an XR_EXT_debug_utils messenger when offered: the validation layer's and
        /// runtime's messages go to the log and are counted (validationMessages()).
        bool debugMessenger = true;
    };
    /// Instance (with XR_KHR_opengl_enable) and the head-mounted system. Throws XrUnavailable.
    explicit XrHeadset(const Options& options);
    ~XrHeadset();
    XrHeadset(const XrHeadset&) = delete;
    XrHeadset& operator=(const XrHeadset&) = delete;

    /// "runtime name version" and the system's name, for the log.
    std::string runtimeName() const;
    std::string systemName() const;
    /// The OpenGL version range the runtime accepts, "major.minor-major.minor".
    std::string glRequirements() const;

    /// The session on the current GL context, its local and view spaces, swapchains and
    /// actions. The context must be current on this thread for every later call.
    void startSession(const GlxBinding& gl);

    /// Handles queued events: begins the session when ready, ends it when stopping. Returns
    /// false once the application should leave its loop (exiting, loss pending, instance
    /// lost); `why` says which.
    bool pollEvents(std::string& why);
    XrState state() const;
    bool running() const;  ///< between xrBeginSession and xrEndSession
    bool focused() const;  ///< input is ours
    /// Asks the runtime to end the session (xrRequestExitSession); the loop continues until
    /// pollEvents says exiting.
    void requestExit();

    XrFrameTiming waitFrame();
    void beginFrame();
    /// Controllers at `time`; all idle unless focused.
    XrControllers syncInput(int64_t time);
    /// Both eyes at `time`, sized to their swapchains; textures are filled by acquireEye.
    std::array<XrEyeView, 2> locateEyes(int64_t time);
    /// Acquires (and waits for) the eye's next swapchain image; returns its GL texture.
    unsigned acquireEye(int eye);
    void releaseEye(int eye);
    /// A panel's swapchain (after startSession); its image is drawn between acquirePanel and
    /// releasePanel, and shown over the scene by endFrame(..., true).
    void createPanel(const XrPanel& panel);
    unsigned acquirePanel();
    void releasePanel();
    /// Submits the frame: both eyes' projection layer when `eyes` (the views locateEyes
    /// returned, drawn and released), then the panel as a quad layer when `panel`; no layer
    /// when `eyes` is null.
    void endFrame(const XrFrameTiming& timing, const std::array<XrEyeView, 2>* eyes,
                  bool panel = false);

    /// A pulse on the pen hand: amplitude 0..1 for `durationNs` (0: the runtime's minimum).
    void vibrate(float amplitude, int64_t durationNs);
    void stopVibration();

    /// Warnings and errors the debug messenger received (validation layer, runtime).
    size_t debugMessages() const;
    uint64_t framesSubmitted() const;

    struct Impl;

  private:
    std::unique_ptr<Impl> mImpl;
};

}  // namespace vsculpt::devices
