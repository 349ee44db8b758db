// The example robots (examples/) the per-robot benchmarks take by index
// (state.range(0)), and their names for the benchmarks' labels.
#pragma once

namespace massid::bench {

inline const char* const kRobots[] = {MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf",
                                      MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf",
                                      MASSID_SOURCE_DIR "/examples/branching/branching.urdf"};
inline const char* const kRobotNames[] = {"puma260", "ur_like", "branching"};

}  // namespace massid::bench
