#!/bin/sh
# Draws the README's figure (doc/images/view-residuals.png) with the tools: the simulated Viper850,
# 25 rendered views (seed 1), calibrated; the report's view_residuals.png is the figure.
#   doc/tools/readme-figure.sh [BUILD_DIR]      (default build)
set -e
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(cd "${1:-$root/build}" && pwd)/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$bin/visp-selfcalib" simulate ds.yaml --images --poses 25 --seed 1
"$bin/visp-selfcalib" calibrate ds.yaml --out result
cp result/report/view_residuals.png "$root/doc/images/view-residuals.png"
echo "wrote doc/images/view-residuals.png"
