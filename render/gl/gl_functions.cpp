#include "gl_functions.h"

namespace clothsim::gl {

thread_local const Functions* current = nullptr;

const char* load_functions(Functions& out, GetProc get_proc, void* user) {
#define CLOTHSIM_GL_LOAD(upper, name)                                              \
  out.name = reinterpret_cast<PFNGL##upper##PROC>(get_proc("gl" #name, user));     \
  if (!out.name) return "gl" #name;
  CLOTHSIM_GL_FUNCTIONS(CLOTHSIM_GL_LOAD)
#undef CLOTHSIM_GL_LOAD
  return nullptr;
}

}  // namespace clothsim::gl
