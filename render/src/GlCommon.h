// SPDX-License-Identifier: MIT
/// @file GlCommon.h
/// @brief Private: GLFW start-up, the clay shader, and the GL error check shared by the
/// offscreen shots and the window.
#pragma once

#include <epoxy/gl.h>  // the GL loader, before anything that includes GL headers

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "vsculpt/core/Mesh.h"
#include "vsculpt/render/Shot.h"
#include "vsculpt/render/Viewer.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace vsculpt::render::detail {

/// Initialises GLFW once per process; throws RenderError when there is no display.
void ensureGlfw();

struct WindowDeleter {
    void operator()(GLFWwindow* w) const { glfwDestroyWindow(w); }
};
using WindowPtr = std::unique_ptr<GLFWwindow, WindowDeleter>;

/// A GL 3.3 core window (hidden unless `visible`), its framebuffer multisampled with
/// `samples` per pixel when the display offers it (1: not).
WindowPtr createWindow(int width, int height, const std::string& title, bool visible,
                       int samples = 1);

/// The clay program: attributes 0 position, 1 normal; uniforms clipFromWorld (mat4),
/// worldFromObject (mat4), eye (vec3, world), tint (vec3, multiplies the grey).
GLuint clayProgram();

/// Compiles and links a program from vertex and fragment sources.
GLuint linkProgram(const char* vertex, const char* fragment);

/// A mesh in GL buffers: positions and normals interleaved (attributes 0 and 1), 32-bit
/// indices. Plain data: release() frees it (the context must be current).
struct GpuMesh {
    GLuint vao = 0, vbo = 0, ibo = 0;
    GLsizei count = 0;
    uint64_t version = 0;
    glm::vec3 lo{0.f}, hi{0.f};  ///< bounds of the positions uploaded (the mesh's frame)
    void release() {
        if (vbo) glDeleteBuffers(1, &vbo);
        if (ibo) glDeleteBuffers(1, &ibo);
        if (vao) glDeleteVertexArrays(1, &vao);
        *this = GpuMesh{};
    }
    void upload(const core::Mesh& m) {
        if (!vao) {
            glGenVertexArrays(1, &vao);
            glGenBuffers(1, &vbo);
            glGenBuffers(1, &ibo);
        }
        std::vector<float> data;
        data.reserve(m.positions.size() * 6);
        lo = glm::vec3(m.positions.empty() ? 0.f : std::numeric_limits<float>::max());
        hi = glm::vec3(m.positions.empty() ? 0.f : std::numeric_limits<float>::lowest());
        for (size_t i = 0; i < m.positions.size(); ++i) {
            lo = glm::min(lo, glm::vec3(m.positions[i]));
            hi = glm::max(hi, glm::vec3(m.positions[i]));
            const core::Vec3 n = i < m.normals.size() ? m.normals[i] : core::Vec3(0, 0, 1);
            for (double v : {m.positions[i].x, m.positions[i].y, m.positions[i].z, n.x, n.y, n.z})
                data.push_back(float(v));
        }
        glBindVertexArray(vao);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(float)), data.data(),
                     GL_STATIC_DRAW);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                              reinterpret_cast<void*>(3 * sizeof(float)));
        glEnableVertexAttribArray(1);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(m.indices.size() * sizeof(uint32_t)),
                     m.indices.data(), GL_STATIC_DRAW);
        count = GLsizei(m.indices.size());
    }
    void draw(GLenum mode = GL_TRIANGLES) const {
        if (!count) return;
        glBindVertexArray(vao);
        glDrawElements(mode, count, GL_UNSIGNED_INT, nullptr);
    }
};

/// The six planes of a view volume (-w <= x, y, z <= w in clip space) in the frame of
/// `clipFromBox`, to test boxes of that frame against.
class ViewPlanes {
  public:
    explicit ViewPlanes(const glm::mat4& clipFromBox);
    /// Whether the box [lo, hi] lies wholly outside: all of it beyond one plane (as all eight
    /// corners would be). Conservative (a box that straddles planes counts as in view), so
    /// skipping such a box never changes a pixel.
    bool outside(const glm::vec3& lo, const glm::vec3& hi) const {
        const glm::vec3 centre = 0.5f * (lo + hi), half = 0.5f * (hi - lo);
        for (const glm::vec4& p : mPlanes)
            if (glm::dot(glm::vec3(p), centre) + p.w + glm::dot(glm::abs(glm::vec3(p)), half) < 0)
                return true;
        return false;
    }

  private:
    glm::vec4 mPlanes[6];
};

/// The GLX handles of a window's context (NativeGl.cpp); throws RenderError off X11/GLX.
NativeGl nativeGl(GLFWwindow* window);

/// Throws RenderError naming the GL error, if any.
void checkGl(const char* what);

}  // namespace vsculpt::render::detail
