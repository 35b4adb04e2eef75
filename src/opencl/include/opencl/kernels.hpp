// The OpenCL C sources of kernels/, embedded into the library at build time
// (cmake/EmbedKernels.cmake writes the definitions into the build tree).
#pragma once

namespace freespace::opencl {

struct KernelFile {
  const char* name;  // file name, e.g. "rasterize.cl"; build logs cite it
  const char* text;  // the file's content
};

extern const KernelFile kKernelFiles[];
extern const int kKernelFileCount;

}  // namespace freespace::opencl
