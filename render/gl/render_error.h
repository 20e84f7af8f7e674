// What the renderer throws when it cannot draw: no GL 3.3 context, a shader that fails to
// compile, a framebuffer that is incomplete. Here, on the GL floor, because that is where
// almost every such failure starts; render/renderer.h and its users catch it from here.
#pragma once

#include <stdexcept>

namespace clothsim {

struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace clothsim
