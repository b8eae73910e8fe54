// Where the build found the repository's data/ and the libcgal-demo meshes. Defined in one
// source file that CMake generates, so that no other translation unit carries an absolute path
// and ccache can share objects between clones in different folders.
#pragma once

namespace freeform::build_paths {

const char* data_dir();
const char* default_mesh_dir();

}  // namespace freeform::build_paths
