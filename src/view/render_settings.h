// How a scene asks to be pictured: image size, frame rate, camera, colouring, overlay and
// anti-aliasing, as the scene's render block gave them. Read by make_render_frame() and the tools.
#pragma once

#include <Eigen/Core>
#include <string>

#include "view/render_frame.h"  // kDefaultMsaaSamples

namespace clothsim {

using Vec3 = Eigen::Vector3d;

struct CameraDef {
  Vec3 eye{0.0, 2.0, -10.0};   // m, the course's default camera
  Vec3 target{0.0, 0.0, 0.0};
  Vec3 up{0.0, 1.0, 0.0};
  double fov = 45.0;            // degrees, vertical
};

struct RenderDef {
  // Bounds the parser and the --width/--height/--fps options both hold values to.
  static constexpr int kMinSize = 16, kMaxSize = 8192;  // pixels
  static constexpr double kMaxFps = 1000.0;              // frames per simulated second (> 0)
  int width = 1280, height = 720;  // pixels
  double fps = 30.0;               // output frames per simulated second
  bool fps_given = false;          // render.fps appeared in the scene (bench --budget's frame, else 60)
  CameraDef camera;
  bool camera_auto = false;        // camera: auto, fitted to the cloth and spheres (camera_fit.h)
  std::string color;               // checker|error|strain|speed; "": the command's default
                                   // (checker for run, error for compare)
  std::string overlay = "full";    // full|label|none: what text is drawn on the pictures
  bool draw_springs = false;       // overlay the springs as lines, as the course's UI did
  bool draw_particles = false;
  int samples = kDefaultMsaaSamples;  // MSAA samples (render.msaa / render.samples)
  bool samples_given = false;      // render.msaa or render.samples appeared in the scene
  std::string antialias;           // msaa|fxaa|none; "": msaa as render.msaa says when it is
                                   // given, else the command's default (msaa for run, fxaa for
                                   // compare's tiles: docs/scenes.md says why)
};

}  // namespace clothsim
