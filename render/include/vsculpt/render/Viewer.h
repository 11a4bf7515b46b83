// SPDX-License-Identifier: MIT
/// @file Viewer.h
/// @brief The sculpting window's drawing side: a GLFW window with an OpenGL 3.3 core
/// context that keeps the polygonizer's chunks on the GPU (re-uploading only chunks whose
/// version changed) and draws them with the tool, in mono, side-by-side or anaglyph stereo.
/// Input is collected as events for the application to map (bindings live in app/). The
/// on-screen UI arrives as a texture (UiImage, drawn by UiLayer) composited into each eye.
#pragma once

#include "vsculpt/core/MeshChunks.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/render/Shot.h"
#include "vsculpt/render/StereoCamera.h"

#include <glm/vec2.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

struct GLFWwindow;

namespace vsculpt::render {

struct InputEvent {
    enum class Kind { Key, MouseButton, Cursor, Scroll, Close, Char };
    Kind kind = Kind::Key;
    int code = 0;  ///< GLFW key or mouse button; Char: the typed Unicode code point
    bool pressed = false;
    double x = 0, y = 0;  ///< cursor position in pixels, or scroll offsets
};

struct ToolDraw {
    bool visible = true;
    core::Vec3 worldPos{0.0};
    double radiusMm = 5;
    /// 0 = in the air, 1 = touching the surface, 2 = inside the material (contact cue).
    int contact = 0;
    bool selectBox = false;  ///< the region-select tool is drawn as a cube
    /// Depth cue: where the tool's shadow falls on the surface straight below it (world -z).
    bool shadow = false;
    core::Vec3 shadowPos{0.0};
    /// The pen's pointing ray to where it meets a panel (world mm), drawn by drawEye: the
    /// headset's pointer (XrPanelUi); the desktop window has the mouse.
    bool pointer = false;
    core::Vec3 pointerFrom{0.0}, pointerTo{0.0};
};

/// Correction for a headset's lenses in side-by-side mode: each eye's image is resampled
/// with radial (barrel) pre-distortion r' = r (1 + k1 r^2 + k2 r^4), r measured from the eye
/// image's centre in units of its half-height, and the red and blue channels scaled by their
/// own factors against the lens's chromatic aberration. All zero/one: no correction.
struct LensCorrection {
    double k1 = 0, k2 = 0;
    double redScale = 1, blueScale = 1;
    bool active() const { return k1 != 0 || k2 != 0 || redScale != 1 || blueScale != 1; }
};

/// The on-screen UI of one frame, rendered offscreen (UiLayer): a premultiplied-alpha RGBA
/// texture the size of one eye's image (eyeImageSize), composited into each eye as a flat
/// quad. In stereo each eye's copy is shifted by the disparity of a plane `depthMm` from the
/// eyes (eyeShiftNdc, rounded to whole pixels so text stays sharp); 0 puts it on the
/// zero-parallax plane (the same place in both eyes, screen depth).
struct UiImage {
    unsigned texture = 0;  ///< GL texture name in the viewer's context; not owned
    int width = 0, height = 0;
    double depthMm = 0;
    /// The part of the texture the UI drew on (pixels, top-left origin, x1/y1 exclusive):
    /// only that is composited (a full-window blend is a few ms on a software renderer).
    int usedX0 = 0, usedY0 = 0, usedX1 = 0, usedY1 = 0;
};

/// The window's GLX handles (X11), for a headset session on the viewer's GL context
/// (OpenXR's XrGraphicsBindingOpenGLXlibKHR). Opaque pointers: no Xlib in this header.
struct NativeGl {
    void* display = nullptr;  ///< Display*
    uint32_t visualId = 0;
    void* fbConfig = nullptr;  ///< GLXFBConfig
    unsigned long drawable = 0;
    void* context = nullptr;  ///< GLXContext
};

struct FrameStats {
    size_t chunksUploaded = 0, chunksDrawn = 0, triangles = 0;
    double cpuMs = 0;  ///< CPU time spent in draw() (upload + draw calls)
};

class Viewer {
  public:
    /// Opens the window (hidden when `visible` is false, e.g. for tests). Throws RenderError
    /// when there is no display. `samples`: the window's samples per pixel (multisample
    /// antialiasing of what draw() puts in it; render.msaa_samples); 1: none; 0: auto, 4 but
    /// 1 on a software rasterizer (Mesa's llvmpipe or softpipe). A display that offers fewer
    /// gives fewer (windowSamples()). The headset's mirror window takes 1: a blit into a
    /// multisampled window is not allowed.
    Viewer(int width, int height, const std::string& title, bool visible, int samples = 1);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    /// Events since the last call (polls the window system).
    std::vector<InputEvent> pollEvents();
    void setTitle(const std::string& title);
    /// Queues an event as if the window system had delivered it (tests and demos drive the
    /// application's real input handling this way); the next pollEvents() returns it.
    void injectEvent(const InputEvent& event);
    int width() const;
    int height() const;

    /// Uploads the chunks whose version changed since the last sync; drops chunks of a
    /// previous polygonizer (zoom change) automatically.
    size_t syncChunks(const core::Polygonizer& view);
    /// The same from a published set (Session::published(), core::AsyncMesher): uploads the
    /// chunks whose version differs from what is on the GPU, frees those that emptied, and
    /// starts afresh when the region differs (zoom change, preview -> full resolution).
    /// Returns the chunks uploaded.
    size_t syncChunks(const core::MeshChunks& chunks);
    /// Draws the scene. `worldFromObject`: the sculpture's pose; the camera frames `focus`
    /// (object space) at `distanceMm`.
    FrameStats draw(const glm::dmat4& worldFromObject, const core::Aabb& frameBox,
                    const ToolDraw& tool, StereoMode mode, const StereoDisplay& display,
                    const LensCorrection& lens = {}, const UiImage* ui = nullptr);
    /// One eye of a headset frame: the chunks, surface lines and tool seen by `eye` (world mm)
    /// drawn into `colorTexture`, a `width` x `height` GL_TEXTURE_2D of this context (a
    /// swapchain image), with the viewer's own depth buffer. No UI, no lens correction (the
    /// headset's compositor corrects).
    FrameStats drawEye(const glm::dmat4& worldFromObject, const ToolDraw& tool, const EyeView& eye,
                       unsigned colorTexture, int width, int height);
    /// Samples per pixel for drawEye (multisample antialiasing: drawn into multisampled
    /// buffers of the swapchain image's format, then resolved into it); 1: off, the default.
    /// Clamped to what the GL offers (GL_MAX_SAMPLES); returns the number used.
    int setEyeSamples(int samples);
    /// Samples per pixel of the window's framebuffer (1: not multisampled).
    int windowSamples() const;
    int eyeSamples() const;
    /// Chunks whose bounds lie wholly outside an eye's view are skipped (on by default; it
    /// changes no pixel, FrameStats counts what was drawn). Off: every chunk is drawn, for
    /// comparisons.
    void setChunkCulling(bool on);
    /// Copies a `width` x `height` texture into the window, scaled to fit (the headset's
    /// mirror on the desktop).
    void blitToWindow(unsigned colorTexture, int width, int height);
    /// Copies a `width` x `height` texture into another of at least that size (the UI's image
    /// into a headset panel's swapchain image).
    void copyTexture(unsigned source, unsigned destination, int width, int height);
    /// The GLX handles of this window's context; throws RenderError when not on X11/GLX.
    NativeGl nativeGl() const;
    /// The size in framebuffer pixels of one eye's image in `mode` (the view area, or half of
    /// it side by side): the size to render the UI at.
    glm::ivec2 eyeImageSize(StereoMode mode) const;
    /// Composites `ui` over the whole framebuffer as it is (mono, no shift): for windows whose
    /// UI spans more than the 3D view (the sketch window).
    void overlayUi(const UiImage& ui);
    /// Where a window pixel falls on the UI texture of the last draw (pixels, top-left
    /// origin, size `uiSize`): through the eye under the pointer side by side (undoing that
    /// eye's shift), through the cyclopean eye in anaglyph (the shifts are symmetric), as is in
    /// mono. For feeding the pointer to the UI.
    glm::dvec2 pointerOnUi(double x, double y, StereoMode mode, glm::ivec2 uiSize) const;
    /// A window pixel in framebuffer pixels (they differ on HiDPI screens): the pointer on a
    /// UI composited with overlayUi.
    glm::dvec2 windowToFramebuffer(double x, double y) const;
    /// The display the last draw used (framing sets focal distance, aspect, clip planes) and
    /// the horizontal UI shift it applied to each eye (NDC, after rounding to pixels).
    const StereoDisplay& lastDisplay() const;
    double lastUiShiftNdc(Eye eye) const;
    /// A tracked head (a headset): the next draws put the eyes at this worldFromHead (mm; head
    /// frame x right, y up, looking down -z) instead of framing the sculpture from the front.
    /// nullopt goes back to framing.
    void setTrackedHead(const std::optional<glm::dmat4>& worldFromHead);
    /// The 3D view draws into framebuffer columns [x, x + width) only (sketch mode puts the
    /// canvas beside it); width 0 restores the whole window. Picking (pixelRay,
    /// pixelToEyeNdc) takes window pixels and follows the area.
    void setViewArea(int x, int width);
    /// Polylines on the sculpture (object space, mm; surface lines drawn on the model), drawn
    /// with it from the next draw on. Uploaded only when they change.
    void setSurfaceLines(const std::vector<std::vector<core::Vec3>>& lines);
    /// The mono camera of the last draw (picking and drawing on the model).
    const EyeView& monoEye() const;
    /// Where a window pixel falls in an eye's NDC (the eye under it in side-by-side mode).
    void pixelToEyeNdc(double x, double y, StereoMode mode, double& ndcX, double& ndcY) const;
    /// Full screen on monitor `index` (0 = primary); false when there is no such monitor.
    bool goFullscreen(int index);
    void swap();
    /// Makes this window's GL context current (needed when an application draws into more
    /// than one window, e.g. the sketch window and its headset view).
    void makeCurrent();
    Image readFrame();

    /// GL_RENDERER and GL_VERSION of the context, for benchmark records.
    std::string rendererName() const;
    /// Waits until the GPU has finished the frame (benchmarks).
    void finish();

    /// The world-space ray through a window pixel, for the current mono camera.
    void pixelRay(double x, double y, core::Vec3& origin, core::Vec3& dir) const;

  private:
    void windowToArea(double& x, int& w) const;
    void compositeUi(const UiImage& ui, double shiftNdc);
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

}  // namespace vsculpt::render
