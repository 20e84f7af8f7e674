// Where clothsim's shipped files are, whether it runs from its build tree or from an
// installed prefix, wherever that prefix was unpacked (docs/install.md):
//   build tree:  build/libexec/clothsim            -> the source tree's scenes/ and tools/
//   installed:   PREFIX/libexec/clothsim/clothsim  -> PREFIX/share/clothsim/{scenes,tools}
//   Python:      PREFIX/lib/python3/dist-packages/clothsim*.so -> the same share/clothsim
// The installed layout is recognised from the path this code was loaded from (dladdr), so a
// copied or relocated prefix works without configuration.
#pragma once

#include <string>

namespace clothsim::clip {

// PREFIX/share/clothsim when this program is an installed one, else "".
std::string installed_data_dir();

// The shipped scenes' folder: the installed one, else the source tree's.
std::string shipped_scenes_dir();

// What a SCENE argument names: the path as given when it exists or names a folder
// ("scenes/drape.yaml", "./x.yaml"); else a bare name of a shipped scene ("drape_smooth",
// "drape_smooth.yaml") in shipped_scenes_dir(); else the argument unchanged, for the parser
// to say it does not exist.
std::string resolve_scene_argument(const std::string& arg);

}  // namespace clothsim::clip
