# Sourced by the scripts that compare this tree with an earlier commit (bench-commit.sh,
# frame-instructions.sh): commit_render COMMIT BUILD sets OLD to that commit's penumbra-render,
# built Release in a git worktree under BUILD/commit-<sha> (kept for the next call only with
# KEEP=1: commit_cleanup removes it otherwise), and short to the commit's 9-digit hash.
commit_render() {
    local commit=$1 build=$2
    short=${commit:0:9}
    COMMIT_TREE=$(realpath -m "$build/commit-$short")
    OLD=$COMMIT_TREE/build/bin/penumbra-render
    if [ ! -x "$OLD" ]; then
        echo "== building $short in $COMMIT_TREE (Release, penumbra-render only)" >&2
        [ -d "$COMMIT_TREE/src" ] || git worktree add --detach "$COMMIT_TREE/src" "$commit" >&2
        cmake -S "$COMMIT_TREE/src" -B "$COMMIT_TREE/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
        cmake --build "$COMMIT_TREE/build" -j"$(nproc)" --target penumbra-render >&2
    fi
}
commit_cleanup() {
    if [ "${KEEP:-0}" != 1 ] && [ -n "${COMMIT_TREE:-}" ]; then
        git worktree remove --force "$COMMIT_TREE/src" 2>/dev/null || true
        rm -rf "$COMMIT_TREE"
    fi
}
