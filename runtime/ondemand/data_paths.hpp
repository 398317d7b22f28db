// Where mechgen finds what generating and compiling a kernel needs: the templates and the header of
// the runtime's CompiledKernel ABI. An installed mechgen (bin/mechgen) finds them in
// <prefix>/share/mechgen/{templates,include}; a build-tree binary in its source tree (templates/,
// runtime/).
#pragma once

#include <string>

namespace mechgen::ondemand {

// The folder holding kernel.hpp.in and kernel_entry.cpp.in.
std::string templates_dir();
// The include folder holding sweep/compiled_kernel.hpp (what <model>_entry.cpp includes).
std::string kernel_include_dir();
// This executable's own identity: its GNU build id (hex) when it has one, else a hash of its file.
// On-demand kernels are cached per identity: another mechgen binary (another generator) builds its
// own.
std::string executable_id();

}  // namespace mechgen::ondemand
