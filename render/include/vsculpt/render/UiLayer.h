// SPDX-License-Identifier: MIT
/// @file UiLayer.h
/// @brief Dear ImGui for a Viewer's window: owns the ImGui context, its OpenGL 3 renderer and
/// an offscreen framebuffer the UI is drawn into once per frame. The Viewer composites that
/// texture into each eye's image (Viewer::draw's UiImage), so in stereo the UI is readable in
/// both eyes and pre-distorted with the scene. Input is fed from the Viewer's events (no GLFW
/// backend): injected test events reach the UI exactly as real ones do. What the panels say
/// and do is the application's (app/), written with the ImGui API between beginFrame() and
/// endFrame().
#pragma once

#include "vsculpt/render/Viewer.h"

#include <memory>

namespace vsculpt::render {

class UiLayer {
  public:
    /// Creates the context for `viewer`'s window (made current here; it must be current for
    /// every call). `viewer` must outlive the layer. Throws RenderError when the UI renderer
    /// cannot start.
    explicit UiLayer(Viewer& viewer);
    ~UiLayer();
    UiLayer(const UiLayer&) = delete;
    UiLayer& operator=(const UiLayer&) = delete;

    /// Hands a key, character, button or scroll event to the UI (call for every event; the
    /// application asks wantsMouse()/wantsKeyboard() whether to act on it too). Cursor
    /// events are not taken here: setPointer() gets the pointer already mapped onto the UI.
    /// A press and release of one key or button within a frame are spread over two frames,
    /// so a quick click is never lost.
    void feed(const InputEvent& event);
    /// The pointer in UI pixels (Viewer::pointerOnUi); off the UI: any negative value.
    void setPointer(double x, double y);

    /// The UI is under the pointer or holds a mouse button (a click belongs to the UI).
    bool wantsMouse() const;
    /// A text field (or another widget) has the keyboard: keys must not run bindings.
    bool wantsKeyboard() const;

    /// Text and widget scale (1 = ImGui's 13 px font); the font is rebuilt at the next frame.
    void setScale(float scale);
    float scale() const;

    /// Starts a UI frame `width` x `height` pixels (Viewer::eyeImageSize), `dtS` seconds after
    /// the last. ImGui calls are valid until endFrame().
    void beginFrame(int width, int height, double dtS);
    /// Renders the frame into the UI texture and returns it for Viewer::draw/overlayUi
    /// (depthMm left 0 for the caller to set).
    UiImage endFrame();

  private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

}  // namespace vsculpt::render
