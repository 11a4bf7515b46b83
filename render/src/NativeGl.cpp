// SPDX-License-Identifier: MIT
// The GLX handles behind a GLFW window, for OpenXR's Xlib graphics binding. Its own file:
// Xlib's macros (None, Bool, Status) stay away from the rest of the renderer.
#include <epoxy/glx.h>

#include "GlCommon.h"

// GLFW's native access (glfw3native.h's X11 and GLX parts), declared here: the header pulls in
// Xrandr's development headers for types these three do not use.
extern "C" {
Display* glfwGetX11Display(void);
GLXContext glfwGetGLXContext(GLFWwindow* window);
GLXWindow glfwGetGLXWindow(GLFWwindow* window);
}

namespace vsculpt::render::detail {

NativeGl nativeGl(GLFWwindow* window) {
    NativeGl n;
    Display* display = glfwGetX11Display();
    GLXContext context = glfwGetGLXContext(window);
    if (!display || !context) throw RenderError("the GL context is not an X11/GLX one");
    n.display = display;
    n.context = context;
    n.drawable = glfwGetGLXWindow(window);
    // The context's framebuffer configuration and visual: asked of GLX, GLFW keeps them.
    int fbConfigId = 0, screen = 0;
    glXQueryContext(display, context, GLX_FBCONFIG_ID, &fbConfigId);
    glXQueryContext(display, context, GLX_SCREEN, &screen);
    const int attributes[] = {GLX_FBCONFIG_ID, fbConfigId, 0};
    int count = 0;
    GLXFBConfig* configs = glXChooseFBConfig(display, screen, attributes, &count);
    if (configs && count > 0) {
        n.fbConfig = configs[0];
        int visual = 0;
        glXGetFBConfigAttrib(display, configs[0], GLX_VISUAL_ID, &visual);
        n.visualId = uint32_t(visual);
    }
    if (configs) XFree(configs);
    return n;
}

}  // namespace vsculpt::render::detail
