#!/usr/bin/env bash
# The main job on the built-in example: set up, build, then run the nhc pipeline on
# examples/appell_hamel.toml and write its outputs to ./out.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
scene=examples/appell_hamel.toml
mkdir -p out
nhc=build/cli/nhc

echo "== nhc derive $scene"
"$nhc" derive "$scene"
"$nhc" derive "$scene" --format latex -o out/appell_hamel.tex
"$nhc" derive "$scene" --format json -o out/appell_hamel.json

echo
echo "== nhc analyze $scene --model chetaev"
"$nhc" analyze "$scene" --model chetaev
"$nhc" analyze "$scene" --model chetaev --format json -o out/appell_hamel_analysis.json
echo
echo "wrote out/appell_hamel.tex"
echo "wrote out/appell_hamel.json"
echo "wrote out/appell_hamel_analysis.json"
