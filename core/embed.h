#pragma once
// A file built with the program (a bundled web script) embedded whole in its
// read-only data: C3D_EMBED_FILE(name, "path") defines
// `std::string_view name()` returning the file's bytes. Use it at namespace
// scope of one .cpp, outside an unnamed namespace, a name unique in the
// program (it names the data's symbols); the path is the build's
// (web/CMakeLists.txt).
#include <cstddef>
#include <string_view>

#define C3D_EMBED_FILE(name, path)                                              \
  __asm__(".pushsection .rodata\n"                                              \
          ".global c3d_embed_" #name "\n.hidden c3d_embed_" #name "\n"          \
          "c3d_embed_" #name ":\n"                                              \
          ".incbin \"" path "\"\n"                                              \
          ".global c3d_embed_" #name "_end\n.hidden c3d_embed_" #name "_end\n"  \
          "c3d_embed_" #name "_end:\n"                                          \
          ".popsection\n");                                                     \
  extern "C" const char c3d_embed_##name[], c3d_embed_##name##_end[];          \
  std::string_view name() { return {c3d_embed_##name, size_t(c3d_embed_##name##_end - c3d_embed_##name)}; }
