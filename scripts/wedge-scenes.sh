# The scenes the wedge benches measure (sourced by bench-potential.sh, bench-tiles.sh and
# bench-commit.sh): every data/ scene with wedges and the stability suite's hard cases, relative
# to the repository root.
wedge_scenes=(data/overlap.json data/plates-three.json data/bars-cross.json data/diamonds.json
              data/parallel-square.json data/plate-tilted.json data/box.json data/sphere.json
              data/torus.json data/torus-box.json data/spheres-nine.json data/demo.json
              data/stability/large-light-small-occluder.json data/stability/light-grazing.json
              data/stability/sphere-grid.json data/stability/plates-stacked.json
              data/stability/faceted-sphere.json data/stability/open-nonmanifold.json
              data/stability/near-clip.json data/stability/camera-in-volume.json
              data/stability/camera-in-wedge.json)
# The same and two levels' spawn views (scene@camera), for the frame benches.
wedge_views=("${wedge_scenes[@]}" ../shared/levels/kaos2.glb@0 ../shared/levels/oa_dm5.glb@0)
# wedge_view ENTRY: sets scene (the file), camera (penumbra-render's --camera arguments, or
# none) and name (the table's row) from an entry of wedge_views.
wedge_view() {
    scene=${1%@*}
    camera=()
    name=$(basename "$scene" .json)
    if [ "$1" != "$scene" ]; then
        camera=(--camera "${1#*@}")
        name="$(basename "$scene" .glb) camera ${1#*@}"
    fi
}
# wedge_selected_views: sets views to VIEWS (entries as in wedge_views, space-separated) where
# it is set, else to wedge_views.
wedge_selected_views() {
    views=("${wedge_views[@]}")
    [ -z "${VIEWS:-}" ] || read -r -a views <<<"$VIEWS"
}
