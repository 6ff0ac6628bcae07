# Sourced by the scripts that compare this tree with an earlier commit (bench-commit.sh,
# frame-instructions.sh).
# commit_begin COMMIT BUILD: OLD, that commit's penumbra-render, built Release in a git worktree
# under BUILD/commit-<sha> (reused if there; removed on exit unless KEEP=1); short, its 9-digit
# hash; OUT, a scratch folder removed on exit.
commit_begin() {
    local commit=$1 build=$2
    short=${commit:0:9}
    COMMIT_TREE=$(realpath -m "$build/commit-$short")
    OLD=$COMMIT_TREE/build/bin/penumbra-render
    OUT=$(mktemp -d)
    trap commit_cleanup EXIT
    if [ ! -x "$OLD" ]; then
        echo "== building $short in $COMMIT_TREE (Release, penumbra-render only)" >&2
        [ -d "$COMMIT_TREE/src" ] || git worktree add --detach "$COMMIT_TREE/src" "$commit" >&2
        cmake -S "$COMMIT_TREE/src" -B "$COMMIT_TREE/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
        cmake --build "$COMMIT_TREE/build" -j"$(nproc)" --target penumbra-render >&2
    fi
}
commit_cleanup() {
    rm -rf "${OUT:-}"
    if [ "${KEEP:-0}" != 1 ] && [ -n "${COMMIT_TREE:-}" ]; then
        git worktree remove --force "$COMMIT_TREE/src" 2>/dev/null || true
        rm -rf "$COMMIT_TREE"
    fi
}
# commit_subject COMMIT: its subject, cut at 80 characters.
commit_subject() {
    local subject
    subject=$(git log -1 --format='%s' "$1")
    [ ${#subject} -le 80 ] || subject="${subject:0:80}…"
    echo "$subject"
}
# tree_name DOC: this tree's 9-digit HEAD, and " with changes" where the tree differs from it
# but for DOC (the table the script is writing).
tree_name() {
    echo "$(git rev-parse --short=9 HEAD)$(git diff --quiet HEAD -- . ":!$1" 2>/dev/null || echo ' with changes')"
}
# The CPU's model name.
cpu_name() {
    grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'
}
