// SPDX-License-Identifier: MIT
#include "vsculpt/render/UiLayer.h"

#include "GlCommon.h"

#include <imgui.h>
// ImGui's OpenGL 3 renderer loads its own GL entry points (imgl3w) next to libepoxy's: both
// resolve the same driver functions for the current context.
#include <backends/imgui_impl_opengl3.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

namespace vsculpt::render {

namespace {

/// The ImGui context: destroyed with the layer.
struct ContextDeleter {
    void operator()(ImGuiContext* c) const { ImGui::DestroyContext(c); }
};

constexpr int kKeys = 512;  // ImGui 1.86's io.KeysDown size; GLFW key codes fit below it

// Debian's ImGui is a static library: the linker takes only the parts this file calls. The
// application's panels must use this library's copy (another copy would have its own, empty
// current context), so the widget, table and std::string parts are pulled in here too.
using InputTextFn = bool (*)(const char*, std::string*, ImGuiInputTextFlags, ImGuiInputTextCallback,
                             void*);
[[gnu::used]] const void* const kImGuiParts[] = {
    reinterpret_cast<const void*>(
        static_cast<bool (*)(const char*, const ImVec2&)>(&ImGui::Button)),
    reinterpret_cast<const void*>(&ImGui::BeginTable),
    reinterpret_cast<const void*>(static_cast<InputTextFn>(&ImGui::InputText))};

}  // namespace

struct UiLayer::Impl {
    Viewer* viewer = nullptr;  // whose GL context holds the texture and the renderer
    std::unique_ptr<ImGuiContext, ContextDeleter> context;
    bool rendererUp = false;
    GLuint fbo = 0, color = 0;
    int width = 0, height = 0;
    float scale = 1, builtScale = 0;
    bool wantsMouse = false, wantsKeyboard = false;
    // The texture's part the last frame drew on (x0, y0, x1, y1; pixels, top-left origin).
    int used[4] = {0, 0, 0, 0};
    // Presses seen this frame, and releases of those presses held back to the next frame
    // (ImGui 1.86 samples button and key state once per frame).
    std::vector<int> keysPressed, keysReleaseLater, buttonsPressed, buttonsReleaseLater;

    void use() const { ImGui::SetCurrentContext(context.get()); }
    void releaseTarget() {
        if (fbo) glDeleteFramebuffers(1, &fbo);
        if (color) glDeleteTextures(1, &color);
        fbo = color = 0;
    }
};

UiLayer::UiLayer(Viewer& viewer) : mImpl(std::make_unique<Impl>()) {
    viewer.makeCurrent();
    mImpl->viewer = &viewer;
    mImpl->context.reset(ImGui::CreateContext());
    mImpl->use();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the user's working folder
    io.LogFilename = nullptr;
    io.BackendPlatformName = "vsculpt";
    // Navigation keys for text fields and widgets, in GLFW's codes (the events' codes).
    const std::pair<ImGuiKey, int> keys[] = {{ImGuiKey_Tab, GLFW_KEY_TAB},
                                             {ImGuiKey_LeftArrow, GLFW_KEY_LEFT},
                                             {ImGuiKey_RightArrow, GLFW_KEY_RIGHT},
                                             {ImGuiKey_UpArrow, GLFW_KEY_UP},
                                             {ImGuiKey_DownArrow, GLFW_KEY_DOWN},
                                             {ImGuiKey_PageUp, GLFW_KEY_PAGE_UP},
                                             {ImGuiKey_PageDown, GLFW_KEY_PAGE_DOWN},
                                             {ImGuiKey_Home, GLFW_KEY_HOME},
                                             {ImGuiKey_End, GLFW_KEY_END},
                                             {ImGuiKey_Insert, GLFW_KEY_INSERT},
                                             {ImGuiKey_Delete, GLFW_KEY_DELETE},
                                             {ImGuiKey_Backspace, GLFW_KEY_BACKSPACE},
                                             {ImGuiKey_Space, GLFW_KEY_SPACE},
                                             {ImGuiKey_Enter, GLFW_KEY_ENTER},
                                             {ImGuiKey_Escape, GLFW_KEY_ESCAPE},
                                             {ImGuiKey_KeyPadEnter, GLFW_KEY_KP_ENTER},
                                             {ImGuiKey_A, GLFW_KEY_A},
                                             {ImGuiKey_C, GLFW_KEY_C},
                                             {ImGuiKey_V, GLFW_KEY_V},
                                             {ImGuiKey_X, GLFW_KEY_X},
                                             {ImGuiKey_Y, GLFW_KEY_Y},
                                             {ImGuiKey_Z, GLFW_KEY_Z}};
    for (const auto& [imgui, glfw] : keys)
        io.KeyMap[imgui] = glfw;
    ImGui::StyleColorsDark();
    if (!ImGui_ImplOpenGL3_Init("#version 330 core"))
        throw RenderError("the UI renderer (Dear ImGui, OpenGL 3) failed to start");
    mImpl->rendererUp = true;
}

UiLayer::~UiLayer() {
    // Another window's context may be current (or none, after it closed): the GL objects are
    // in the viewer's.
    mImpl->viewer->makeCurrent();
    mImpl->use();
    mImpl->releaseTarget();
    if (mImpl->rendererUp) ImGui_ImplOpenGL3_Shutdown();
}

void UiLayer::feed(const InputEvent& e) {
    mImpl->use();
    ImGuiIO& io = ImGui::GetIO();
    auto press = [](bool* down, int i, bool pressed, std::vector<int>& pressedNow,
                    std::vector<int>& later) {
        if (pressed) {
            down[i] = true;
            pressedNow.push_back(i);
        } else if (std::find(pressedNow.begin(), pressedNow.end(), i) != pressedNow.end()) {
            later.push_back(i);  // pressed and released within this frame
        } else {
            down[i] = false;
        }
    };
    switch (e.kind) {
        case InputEvent::Kind::Key:
            if (e.code >= 0 && e.code < kKeys)
                press(io.KeysDown, e.code, e.pressed, mImpl->keysPressed, mImpl->keysReleaseLater);
            break;
        case InputEvent::Kind::MouseButton:
            if (e.code >= 0 && e.code < 5)
                press(io.MouseDown, e.code, e.pressed, mImpl->buttonsPressed,
                      mImpl->buttonsReleaseLater);
            break;
        case InputEvent::Kind::Char:
            if (e.code > 0 && e.code < 0x110000) io.AddInputCharacter(unsigned(e.code));
            break;
        case InputEvent::Kind::Scroll:
            io.MouseWheelH += float(e.x);
            io.MouseWheel += float(e.y);
            break;
        default:
            break;
    }
}

void UiLayer::setPointer(double x, double y) {
    mImpl->use();
    ImGui::GetIO().MousePos =
        x < 0 || y < 0 ? ImVec2(-FLT_MAX, -FLT_MAX) : ImVec2(float(x), float(y));
}

bool UiLayer::wantsMouse() const {
    return mImpl->wantsMouse;
}

bool UiLayer::wantsKeyboard() const {
    return mImpl->wantsKeyboard;
}

void UiLayer::setScale(float scale) {
    mImpl->scale = std::clamp(scale, 0.5f, 4.0f);
}

float UiLayer::scale() const {
    return mImpl->scale;
}

void UiLayer::beginFrame(int width, int height, double dtS) {
    mImpl->use();
    ImGuiIO& io = ImGui::GetIO();
    width = std::max(1, width);
    height = std::max(1, height);
    if (mImpl->builtScale != mImpl->scale) {
        // ImGui's own bitmap font at the scaled pixel size (sharp, unlike FontGlobalScale).
        io.Fonts->Clear();
        ImFontConfig font;
        font.SizePixels = std::round(13.f * mImpl->scale);
        io.Fonts->AddFontDefault(&font);
        ImGui_ImplOpenGL3_DestroyFontsTexture();
        ImGui_ImplOpenGL3_CreateFontsTexture();
        ImGuiStyle style;
        ImGui::StyleColorsDark(&style);
        style.ScaleAllSizes(mImpl->scale);
        ImGui::GetStyle() = style;
        mImpl->builtScale = mImpl->scale;
    }
    if (width != mImpl->width || height != mImpl->height) {
        mImpl->releaseTarget();
        glGenTextures(1, &mImpl->color);
        glBindTexture(GL_TEXTURE_2D, mImpl->color);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     nullptr);
        // Nearest: the texture maps onto the eye's pixels 1:1 (shifts are whole pixels).
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        const float clear[4] = {0, 0, 0, 0};  // outside the texture: nothing (shifted copies)
        glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, clear);
        glGenFramebuffers(1, &mImpl->fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, mImpl->fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, mImpl->color,
                               0);
        const bool complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (!complete) throw RenderError("UI framebuffer incomplete");
        mImpl->width = width;
        mImpl->height = height;
        const int all[4] = {0, 0, width, height};  // new texture: clear all of it once
        std::copy(all, all + 4, mImpl->used);
    }
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DisplayFramebufferScale = ImVec2(1, 1);
    io.DeltaTime = float(std::clamp(dtS, 1e-4, 1.0));
    io.KeyCtrl = io.KeysDown[GLFW_KEY_LEFT_CONTROL] || io.KeysDown[GLFW_KEY_RIGHT_CONTROL];
    io.KeyShift = io.KeysDown[GLFW_KEY_LEFT_SHIFT] || io.KeysDown[GLFW_KEY_RIGHT_SHIFT];
    io.KeyAlt = io.KeysDown[GLFW_KEY_LEFT_ALT] || io.KeysDown[GLFW_KEY_RIGHT_ALT];
    io.KeySuper = io.KeysDown[GLFW_KEY_LEFT_SUPER] || io.KeysDown[GLFW_KEY_RIGHT_SUPER];
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    // This frame has seen the presses; the held-back releases count from the next one.
    for (int k : mImpl->keysReleaseLater)
        io.KeysDown[k] = false;
    for (int b : mImpl->buttonsReleaseLater)
        io.MouseDown[b] = false;
    mImpl->keysPressed.clear();
    mImpl->keysReleaseLater.clear();
    mImpl->buttonsPressed.clear();
    mImpl->buttonsReleaseLater.clear();
}

UiImage UiLayer::endFrame() {
    mImpl->use();
    ImGuiIO& io = ImGui::GetIO();
    ImGui::Render();
    // Decided after the frame's widgets: a field activated this frame already has the
    // keyboard for the events of the next (io's flags would lag a frame behind).
    mImpl->wantsMouse = io.WantCaptureMouse || ImGui::IsAnyItemActive() ||
                        ImGui::IsWindowHovered(ImGuiHoveredFlags_AnyWindow);
    mImpl->wantsKeyboard =
        io.WantTextInput || ImGui::IsAnyItemActive() ||
        ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId | ImGuiPopupFlags_AnyPopupLevel);
    // What this frame draws on: the union of its commands' clip rectangles. Only that part is
    // composited, and only it and the last frame's part are cleared (a software renderer
    // pays for every pixel).
    const ImDrawData* data = ImGui::GetDrawData();
    int now[4] = {mImpl->width, mImpl->height, 0, 0};
    for (int l = 0; data && l < data->CmdListsCount; ++l)
        for (const ImDrawCmd& cmd : data->CmdLists[l]->CmdBuffer) {
            now[0] = std::min(now[0], std::max(0, int(std::floor(cmd.ClipRect.x))));
            now[1] = std::min(now[1], std::max(0, int(std::floor(cmd.ClipRect.y))));
            now[2] = std::max(now[2], std::min(mImpl->width, int(std::ceil(cmd.ClipRect.z))));
            now[3] = std::max(now[3], std::min(mImpl->height, int(std::ceil(cmd.ClipRect.w))));
        }
    int clear[4] = {std::min(now[0], mImpl->used[0]), std::min(now[1], mImpl->used[1]),
                    std::max(now[2], mImpl->used[2]), std::max(now[3], mImpl->used[3])};
    GLint previous = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previous);
    glBindFramebuffer(GL_FRAMEBUFFER, mImpl->fbo);
    glViewport(0, 0, mImpl->width, mImpl->height);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(0, 0, 0, 0);
    if (clear[2] > clear[0] && clear[3] > clear[1]) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(clear[0], mImpl->height - clear[3], clear[2] - clear[0], clear[3] - clear[1]);
        glClear(GL_COLOR_BUFFER_BIT);
        glDisable(GL_SCISSOR_TEST);
    }
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    std::copy(now, now + 4, mImpl->used);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(previous));
    detail::checkGl("UiLayer::endFrame");
    UiImage img;
    img.texture = mImpl->color;
    img.width = mImpl->width;
    img.height = mImpl->height;
    img.usedX0 = now[0];
    img.usedY0 = now[1];
    img.usedX1 = now[2];
    img.usedY1 = now[3];
    return img;
}

}  // namespace vsculpt::render
