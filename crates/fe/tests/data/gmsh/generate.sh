#!/bin/sh
# Regenerate the Gmsh test meshes of crates/fe/tests/solid_*.rs (Gmsh 4.8.4, Debian package).
# Run from this folder: sh generate.sh
set -e
for v in 41 22; do gmsh -3 block.geo -format msh$v -o block_tet4_$v.msh; done
gmsh -3 -order 2 block.geo -format msh41 -o block_tet10.msh
gmsh -3 bar.geo -format msh41 -o bar_hex8.msh
gmsh -3 -order 2 -setnumber Mesh.SecondOrderIncomplete 1 bar.geo -format msh22 -o bar_hex20_22.msh
