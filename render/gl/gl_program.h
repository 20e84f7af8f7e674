// Compiling and linking GLSL programs, and turning GL failures into RenderError.
// Needs a current context (the Renderer makes its own current before calling these).
#pragma once

#include <string>

#include "gl_functions.h"  // the GL names, bound to the current context's entry points

namespace clothsim::gl {

// Compiles both stages and links them; throws RenderError with the compiler log, naming `name`.
GLuint build_program(const std::string& name, const std::string& vertex_source,
                     const std::string& fragment_source);

// Throws RenderError("OpenGL error 0x0505 (GL_OUT_OF_MEMORY) while <what>") if GL reported one.
void check_gl(const std::string& what);

}  // namespace clothsim::gl
