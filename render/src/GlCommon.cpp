// SPDX-License-Identifier: MIT
#include "GlCommon.h"

#include <cstdio>

namespace vsculpt::render::detail {

namespace {

std::string& lastError() {
    static std::string e;
    return e;
}

struct GlfwLibrary {
    bool ok = false;
    std::string error;
    GlfwLibrary() {
        glfwSetErrorCallback([](int, const char* d) { lastError() = d; });
        ok = glfwInit() == GLFW_TRUE;
        if (!ok) error = lastError();
    }
    ~GlfwLibrary() {
        if (ok) glfwTerminate();
    }
};

GLuint compile(GLenum type, const char* src) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        throw RenderError(std::string("shader compile error: ") + log);
    }
    return s;
}

const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 clipFromWorld;
uniform mat4 worldFromObject;
uniform vec3 eye;
out vec3 vNormal;
out vec3 vToEye;
void main() {
    vec4 world = worldFromObject * vec4(position, 1.0);
    vNormal = mat3(worldFromObject) * normal;
    vToEye = eye - world.xyz;
    gl_Position = clipFromWorld * world;
})";

const char* kFragment = R"(#version 330 core
in vec3 vNormal;
in vec3 vToEye;
uniform vec3 tint;
out vec4 color;
void main() {
    // Grey clay lit from the eye (a headlight) plus ambient, the same in every channel (an
    // anaglyph carries one eye per channel); the tool is tinted.
    vec3 n = normalize(vNormal);
    float lambert = max(dot(n, normalize(vToEye)), 0.0);
    float g = 0.18 + 0.72 * lambert;
    color = vec4(g * tint, 1.0);
})";

}  // namespace

void ensureGlfw() {
    static GlfwLibrary glfw;
    if (!glfw.ok)
        throw RenderError("cannot open a display for OpenGL (" + glfw.error +
                          "); on a machine without one, run under xvfb-run; `vsculpt play` without "
                          "--shot and `vsculpt render` need none");
}

WindowPtr createWindow(int width, int height, const std::string& title, bool visible, int samples) {
    ensureGlfw();
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    // A soft constraint: a display without multisampled visuals gives a plain window.
    glfwWindowHint(GLFW_SAMPLES, samples > 1 ? samples : 0);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    WindowPtr window(glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr));
    if (!window) throw RenderError("cannot create an OpenGL 3.3 core context: " + lastError());
    glfwMakeContextCurrent(window.get());
    return window;
}

GLuint linkProgram(const char* vertex, const char* fragment) {
    const GLuint program = glCreateProgram();
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex), fs = compile(GL_FRAGMENT_SHADER, fragment);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        throw RenderError(std::string("shader link error: ") + log);
    }
    return program;
}

GLuint clayProgram() {
    return linkProgram(kVertex, kFragment);
}

ViewPlanes::ViewPlanes(const glm::mat4& clipFromBox) {
    // A point p is inside where w + x >= 0, w - x >= 0, ... with (x, y, z, w) = clipFromBox p:
    // each plane is the last row plus or minus one of the first three.
    auto row = [&](int r) {
        return glm::vec4(clipFromBox[0][r], clipFromBox[1][r], clipFromBox[2][r],
                         clipFromBox[3][r]);
    };
    for (int a = 0; a < 3; ++a) {
        mPlanes[2 * a] = row(3) + row(a);
        mPlanes[2 * a + 1] = row(3) - row(a);
    }
}

void checkGl(const char* what) {
    if (const GLenum err = glGetError(); err != GL_NO_ERROR) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%04x", err);
        throw RenderError(std::string("OpenGL error ") + hex + " in " + what);
    }
}

}  // namespace vsculpt::render::detail
