// What the process may still allocate under an address-space limit (ulimit -v, RLIMIT_AS), so
// that a factorization too large for it is refused with its size up front. Inside CHOLMOD and
// OpenBLAS a failed allocation is not always survivable: OpenBLAS retries its 128 MB work
// buffers forever, and cholmod_solve can crash on a failed workspace allocation.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace freeform {

// Bytes of address space left under RLIMIT_AS (the limit minus the current virtual size), or
// nullopt when there is no limit. Cheap without a limit (one getrlimit call).
std::optional<std::size_t> address_space_headroom();

// Throws OutOfMemory "out of memory while <what>: it needs about N MB, the process may allocate
// M MB more (ulimit -v)" with what = describe(); the message is built only then (solves call
// this once per nonlinear iteration).
[[noreturn]] void throw_out_of_memory(const std::string& what, std::size_t bytes, std::size_t left);

// Throws as above when `bytes` exceed the headroom; does nothing without a limit.
template <class Describe>
void require_memory(std::size_t bytes, const Describe& describe) {
  if (const std::optional<std::size_t> left = address_space_headroom(); left && bytes > *left)
    throw_out_of_memory(describe(), bytes, *left);
}

// For an allocation that failed without saying its size (std::bad_alloc): "out of memory", with
// the address-space limit when there is one.
std::string out_of_memory_message();

// Address space OpenBLAS reserves for its work buffers when the first LAPACK/BLAS call of a
// thread needs one: 128 MB per thread in Debian's build, for its own threads and the pool's
// (0 when the BLAS is not OpenBLAS).
std::size_t blas_buffer_bytes();

}  // namespace freeform
