#!/usr/bin/env bash
# Runs a command where Debian's SuiteSparse, METIS, fmt and OpenBLAS libraries cannot be loaded,
# as on a Linux without them: in a private mount namespace each of their files is covered by
# an empty one, and OpenBLAS's BLAS and LAPACK (which numpy and Blender link) by the reference
# ones. Proves that the wheel and the Blender add-on load only what they bundle (docs/python.md).
#   scripts/without-system-libs.sh COMMAND [ARGS...]
# Needs root (or a user namespace) for `unshare`; exits 77 (skip) where namespaces are refused.
set -euo pipefail
lib=/usr/lib/x86_64-linux-gnu
if [ "${1:-}" != --inside ]; then
  probe=$(readlink -f "$lib/libfmt.so.9" 2>/dev/null || true)
  if ! unshare -m --propagation private sh -c "mount --bind /dev/null '${probe:-/dev/null}'" 2>/dev/null; then
    echo "without-system-libs: mount namespaces or bind mounts are refused here (unshare -m)" >&2
    exit 77
  fi
  exec unshare -m --propagation private "$0" --inside "$@"
fi
shift
hidden=0
for f in "$lib"/lib{cholmod,umfpack,amd,camd,colamd,ccolamd,suitesparseconfig,spqr,metis,fmt}.so.* \
         "$lib"/openblas-pthread/libopenblas*.so*; do
  [ -f "$f" ] && [ ! -L "$f" ] || continue
  mount --bind /dev/null "$f"
  hidden=$((hidden + 1))
done
for api in blas lapack; do
  [ -f "$lib/$api/lib$api.so.3" ] && mount --bind "$lib/$api/lib$api.so.3" "$lib/openblas-pthread/lib$api.so.3"
done
echo "without-system-libs: $hidden library files hidden" >&2
exec "$@"
