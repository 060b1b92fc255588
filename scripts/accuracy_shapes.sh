# The real shapes the accuracy tables judge (sourced by scripts/accuracy_meshes.sh and
# results/accuracy/structures/run.sh): name|mesh|sampling, 10^5 points sampled on each mesh by
# area, and one scanner-like variant (noise 0.3 h, density falling by half across the object, PCA
# normals).
# shellcheck disable=SC2034  # read by the scripts that source this file
accuracy_shapes=(
  "bunny|data/bunny/bunny.off|n=100000"
  "cow|data/cgal/meshes/cow.off|n=100000"
  "elk|data/cgal/meshes/elk.off|n=100000"
  "camel|data/cgal/meshes/camel.off|n=100000"
  "blade|data/cgal/meshes/blade.off|n=100000"
  "bear|data/cgal/meshes/bear.off|n=100000"
  "homer|data/cgal/meshes/homer.off|n=100000"
  "bunny_scan|data/bunny/bunny.off|n=100000,noise=0.3,density=0.5,normals=estimated"
)
