# Sourced by the bench scripts that compare with an earlier revision:
#   buildOld REV TARGET...   builds REV's TARGETs in build-bench-old/build (REV checked out
#                            as a git worktree in build-bench-old/src; reused while REV is
#                            the same) and sets oldBuild to that folder.
buildOld() {
  local rev=$1; shift
  oldBuild=build-bench-old/build
  if [ ! -d build-bench-old/src ] || [ "$(cat build-bench-old/rev 2>/dev/null)" != "$rev" ]; then
    rm -rf build-bench-old && git worktree prune
    git worktree add --detach build-bench-old/src "$rev" >/dev/null
    cmake -S build-bench-old/src -B "$oldBuild" -DCMAKE_BUILD_TYPE=Release -DWAVEMMLT_TESTS=OFF >/dev/null
    echo "$rev" > build-bench-old/rev
  fi
  cmake --build "$oldBuild" -j"$(nproc)" --target "$@" >/dev/null
}
