# The scenes the wedge benches measure (sourced by bench-potential.sh and bench-tiles.sh): every
# data/ scene with wedges and the stability suite's hard cases, relative to the repository root.
wedge_scenes=(data/overlap.json data/plates-three.json data/bars-cross.json data/diamonds.json
              data/parallel-square.json data/plate-tilted.json data/box.json data/sphere.json
              data/torus.json data/torus-box.json data/spheres-nine.json data/demo.json
              data/stability/large-light-small-occluder.json data/stability/light-grazing.json
              data/stability/sphere-grid.json data/stability/plates-stacked.json
              data/stability/faceted-sphere.json data/stability/open-nonmanifold.json
              data/stability/near-clip.json data/stability/camera-in-volume.json
              data/stability/camera-in-wedge.json)
