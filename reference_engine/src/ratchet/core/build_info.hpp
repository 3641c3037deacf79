// Which engine this is, fixed when it was built (run.json "engine", sweep completion;
// docs/output-format.md, docs/sweeps.md). Defined in a file generated at every build
// (reference_engine/cmake/build_info.cmake), its own library ratchet_build_info, so the
// engine sources are the same whatever the commit.
#pragma once

namespace ratchet {

// git HEAD of the source tree at build time (40 hex digits), with "+modified" when
// tracked files differed from it; "unknown" when the sources were not a git checkout
// (e.g. a release tarball).
const char* engine_commit();

// 16 hex digits of SHA-256 over the engine's sources, CMake files, build type and
// compiler: it changes whenever the results could, and needs no git.
const char* engine_source_hash();

// The compiler the hash covers, as CMake names it ("GNU 12.2.0").
const char* engine_compiler();

}  // namespace ratchet
