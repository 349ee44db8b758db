# Toolchain file: massid cross-compiled for aarch64 Linux with Debian's
# g++-aarch64-linux-gnu, its libraries from the sysroot that scripts/arm.sh
# unpacks, its tests run under qemu-user (docs/embedding-arm.md):
#
#   cmake -S . -B build/aarch64/build --toolchain cmake/aarch64-linux-gnu.cmake -DMASSID_EMULATOR=OFF ...
#
# MASSID_ARM_SYSROOT (environment or cache): the unpacked arm64 packages
# (default build/aarch64/sysroot of this source tree).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

if(NOT MASSID_ARM_SYSROOT)
  if(DEFINED ENV{MASSID_ARM_SYSROOT})
    set(MASSID_ARM_SYSROOT $ENV{MASSID_ARM_SYSROOT})
  else()
    get_filename_component(MASSID_ARM_SYSROOT "${CMAKE_CURRENT_LIST_DIR}/../build/aarch64/sysroot"
                           ABSOLUTE)
  endif()
endif()
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES MASSID_ARM_SYSROOT)

# Packages, libraries and headers from the sysroot and the cross compiler's
# own tree only; programs (python3, ...) from the host.
set(CMAKE_FIND_ROOT_PATH ${MASSID_ARM_SYSROOT} /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# Headers no package's CMake file names (fast_float) are in the sysroot too:
# searched after every other directory, as a system directory.
set(CMAKE_CXX_STANDARD_INCLUDE_DIRECTORIES ${MASSID_ARM_SYSROOT}/usr/include)

# The sysroot's shared libraries need others (libceres.so: glog, cholmod, ...):
# the linker finds them there (-rpath-link), and so does the dynamic loader
# under qemu (LD_LIBRARY_PATH). The C and C++ runtimes are the cross
# compiler's (/usr/aarch64-linux-gnu/lib, also the loader's prefix -L), first
# in the path: on a machine with Debian's own arm64 libc6 installed
# (multi-arch), the loader would otherwise take /lib/aarch64-linux-gnu's libc,
# of another build than the loader's, and a program hangs in pthread_create.
set(_massid_arm_libs
    "${MASSID_ARM_SYSROOT}/usr/lib/aarch64-linux-gnu:${MASSID_ARM_SYSROOT}/lib/aarch64-linux-gnu")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,-rpath-link,${_massid_arm_libs}")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,-rpath-link,${_massid_arm_libs}")
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu -E
                                  LD_LIBRARY_PATH=/usr/aarch64-linux-gnu/lib:${_massid_arm_libs})
