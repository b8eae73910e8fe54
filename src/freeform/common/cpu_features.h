// What the running CPU can do, for kernels compiled twice (the build's baseline ISA and a wider
// one picked at run time): users' default builds get wide vectors without -march=native.
#pragma once

namespace freeform {

// x86-64 with AVX2 and FMA (false on other architectures and compilers).
bool cpu_has_avx2_fma();

}  // namespace freeform
