#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, builds the
# HFTS databases of every bundled object and the hand reachability maps,
# starts the planning service (hfts-server) for the three bundled robots,
# plans a grasp and a path to it in a bundled scene with hfts-client (the
# KR5 + SDH, then the UR5e), stops the server, and finally plans in each
# bundled scene with hfts-bench.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh --target hfts-preprocess hfts-server hfts-client hfts-bench hfts-validate
echo
echo "== Building the HFTS databases of objects/meshes into build/databases"
build/bin/hfts-preprocess objects/meshes -o build/databases
echo
echo "== One of them: build/bin/hfts-preprocess --inspect build/databases/mug.h5"
build/bin/hfts-preprocess --inspect build/databases/mug.h5
echo
echo "== The hand reachability maps of the bundled robots (KR5 + SDH, Panda, UR5e + Allegro-like hand)"
for robot in kr5_sdh panda_gripper ur5e_allegro; do
  build/bin/hfts-preprocess --hand "robots/$robot/$robot.json" -o build/databases
done
echo
echo "== The bundled scenes as glTF (open them in any glTF viewer, or scripts/render_glb.py)"
for scene in objects/scenes/*.json; do
  build/bin/hfts-preprocess --export-scene "$scene" "build/$(basename "$scene" .json).glb"
done
echo
echo "== The planning service: hfts-server on a free port for the three robots (docs/protocol.md)"
build/bin/hfts-server --db build/databases --port 0 --robot robots/kr5_sdh/kr5_sdh.json \
  --robot robots/panda_gripper/panda_gripper.json --robot robots/ur5e_allegro/ur5e_allegro.json \
  >build/demo_server.out 2>build/demo_server.log &
server=$!
# Stop the server however this script ends (SIGTERM: it shuts down gracefully).
trap 'kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true' EXIT
for _ in $(seq 1 600); do  # up to a minute: three robots rate every object at start
  grep -q "listening on" build/demo_server.out 2>/dev/null && break
  kill -0 "$server" 2>/dev/null || break
  sleep 0.1
done
port=$(sed -n 's/^hfts-server listening on .*:\([0-9]*\)$/\1/p' build/demo_server.out)
if [[ -z "$port" ]]; then
  echo "demo: hfts-server did not start:" >&2
  cat build/demo_server.log >&2
  exit 1
fi
cat build/demo_server.out
build/bin/hfts-client --port "$port" info
echo
echo "== A grasp and a path in the table scene, checked in physics:"
echo "   build/bin/hfts-client --port $port plan --scene table --validate"
rm -f build/demo_plan.glb build/demo_plan.html build/demo_trajectory.csv
# 60 s: every goal the search reaches is simulated (seconds each); this one
# took 22.6 s on a busy 2-core machine.
build/bin/hfts-client --port "$port" --out build/demo_plan.json plan --scene table --seed 1 \
  --time-limit 60 --validate --gltf build/demo_plan.glb --trajectory-csv build/demo_trajectory.csv ||
  [[ $? -eq 3 ]]  # 3: no plan within the time limit (printed above)
if [[ -f build/demo_plan.json ]] && grep -q '"success": true' build/demo_plan.json; then
  echo
  echo "== The plan's grasp in physics, trial by trial: build/bin/hfts-validate build/demo_plan.json"
  build/bin/hfts-validate --db build/databases build/demo_plan.json || [[ $? -eq 1 ]]  # 1: not held
fi
echo "(the whole result as JSON: build/demo_plan.json; the server's log: build/demo_server.log)"
if [[ -f build/demo_plan.glb ]]; then
  build/bin/hfts-client view build/demo_plan.json -o build/demo_plan.html
  echo "(open build/demo_plan.html in a web browser to watch the plan: play, scrub, orbit;"
  echo " the animation alone, build/demo_plan.glb, plays in any glTF viewer, e.g. Blender;"
  echo " the trajectory as CSV: build/demo_trajectory.csv; docs/viewer.md, docs/trajectories.md)"
fi
echo
echo "== The same scene with the UR5e and its four-fingered hand: ... plan --robot ur5e_allegro"
build/bin/hfts-client --port "$port" plan --robot ur5e_allegro --scene table --seed 1 \
  --time-limit 30 || [[ $? -eq 3 ]]
build/bin/hfts-client --port "$port" shutdown
wait "$server"
trap - EXIT
echo
echo "== Grasp and motion planning in each bundled scene with hfts-bench (coupled planner, seed 1;"
echo "   success is a plan whose grasp holds in physics)"
build/bin/hfts-bench --db build/databases --algorithms coupled --runs 1 --time-limit 30 \
  --out build/demo_plans.csv
echo
echo "To look at the partition: build/bin/hfts-preprocess --export-ply build/databases/mug.h5 mug.ply"
