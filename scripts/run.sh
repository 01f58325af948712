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
echo "== nhc generate $scene --model chetaev"
"$nhc" generate "$scene" --model chetaev -o out
echo
echo "== nhc simulate $scene (header, compile, integrate)"
"$nhc" simulate "$scene" -o out/appell_hamel.csv
echo
echo "== nhc simulate $scene --t-end 0.3: past t*, where the constraint gradient is singular (exit 3)"
"$nhc" simulate "$scene" --t-end 0.3 -o out/appell_hamel_t_star.csv || [ $? -eq 3 ]
echo
echo "wrote out/appell_hamel.tex"
echo "wrote out/appell_hamel.json"
echo "wrote out/appell_hamel_analysis.json"
echo "wrote out/appell_hamel_chetaev.hpp"
echo "wrote out/appell_hamel.csv"
echo "wrote out/appell_hamel_t_star.csv"
echo
echo "== nhc report $scene: work-precision (error against run time, rtol 1e-3 ... 1e-12)"
"$nhc" report "$scene" -o out/appell_hamel_report
echo "wrote out/appell_hamel_report/report.md (workprec.csv, workprec.svg, workprec.png)"
