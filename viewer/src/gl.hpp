#pragma once
// The one place the viewer includes OpenGL: OSMesa exports every core entry point, so the
// prototypes are used directly (no loader needed).
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>
