// SPDX-License-Identifier: MIT
/// @file GlCommon.h
/// @brief Private: GLFW start-up, the clay shader, and the GL error check shared by the
/// offscreen shots and the window.
#pragma once

#include <epoxy/gl.h>  // the GL loader, before anything that includes GL headers

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "vsculpt/render/Shot.h"

#include <memory>
#include <string>

namespace vsculpt::render::detail {

/// Initialises GLFW once per process; throws RenderError when there is no display.
void ensureGlfw();

struct WindowDeleter {
    void operator()(GLFWwindow* w) const { glfwDestroyWindow(w); }
};
using WindowPtr = std::unique_ptr<GLFWwindow, WindowDeleter>;

/// A GL 3.3 core window (hidden unless `visible`).
WindowPtr createWindow(int width, int height, const std::string& title, bool visible);

/// The clay program: attributes 0 position, 1 normal; uniforms clipFromWorld (mat4),
/// worldFromObject (mat4), eye (vec3, world), tint (vec3, multiplies the grey).
GLuint clayProgram();

/// Compiles and links a program from vertex and fragment sources.
GLuint linkProgram(const char* vertex, const char* fragment);

/// Throws RenderError naming the GL error, if any.
void checkGl(const char* what);

}  // namespace vsculpt::render::detail
