// The one way Veil includes OpenGL: libepoxy resolves entry points for EGL and GLFW
// contexts alike. Include this before anything that might pull in another GL header.
#pragma once

#include <epoxy/gl.h>
