#!/bin/bash
# Issue 55 investigation: IE against BDF2 on the S-start and variants. Runs sequentially (one
# simulation at a time). Usage: ./run.sh [GROUP...]; every line goes to runs/table.tsv.
# Everything, in the order it was measured:
#   ./run.sh base base_fine tol perturb locate variants ctol ens m200 fine cond iedt bdf2fine slap m50 m50fine soft landing landing2 m200fine analyse
# and in the second session (rod damping):
#   ./run.sh damping_landing damping_s_start damping_5ms normal_always
# s_start.toml and serpenoid.toml are copies of the bundled problems/ files.
# Runs in WORK (default out/ie_bdf2 in the repository), with the bundled S-start and serpenoid
# and this folder's scripts and landing scenes copied there; SLITHER names the binary (default:
# the repository's release build, built first by tools/build.sh).
set -u
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
work="${WORK:-$repo/out/ie_bdf2}"
mkdir -p "$work/runs"
. "$repo/tools/build.sh"
use_slither || exit 1
B="$SLITHER"
cp "$repo/problems/s_start.toml" "$repo/problems/serpenoid.toml" "$here"/*.toml "$here"/*.py "$work/"
cd "$work"
T=runs/table.tsv
[ -f $T ] || printf "label\tintegrator\telements\tdt\tv_s/v_m\tcx\tcy\thead_x\thead_y\televation/a\tsteps\tnewton/step\tfallbacks\thalvings\twall_s\tstatus\tregime\n" > $T
# r LABEL FILE INTEGRATOR ELEMENTS DT [--set ...]
r() {
  local label=$1 file=$2 integ=$3 el=$4 dt=$5; shift 5
  local out=runs/${label}_${integ}_${el}_${dt}
  if [ ! -f $out/summary.json ]; then
    $B run $file --out $out --no-plots --quiet --force \
      --set solver.integrator=$integ --set rod.elements=$el --set time.dt=$dt "$@" > $out.log 2>&1
  fi
  python3 summ.py $label $integ $el $dt $out | tee -a $T
}
for g in "$@"; do
case $g in
base)   # the S-start at 100 elements
  for dt in 1e-3 5e-4 2.5e-4 1.25e-4; do for i in implicit bdf2; do r base s_start.toml $i 100 $dt; done; done ;;
base_fine)   # smaller steps at 100 elements
  for dt in 6.25e-5 3.125e-5; do for i in implicit bdf2; do r base s_start.toml $i 100 $dt; done; done ;;
tol)    # (e) Newton tolerance 1e-8 instead of 5e-6
  for dt in 1e-3 5e-4 2.5e-4 1.25e-4; do for i in implicit bdf2; do r tol8 s_start.toml $i 100 $dt --set solver.tolerance=1e-8; done; done ;;
perturb)   # sensitivity: relative perturbations of 1e-7 in mu_forward, 1e-6 in gait speed, 1 nm initial height
  for dt in 2.5e-4 1.25e-4; do for i in implicit bdf2; do
    r pmu s_start.toml $i 100 $dt --set ground.mu_forward=0.550000055
    r pvm s_start.toml $i 100 $dt --set gait.speed=0.28000028
    r ph s_start.toml $i 100 $dt --set initial.height=1e-9
  done; done ;;
locate)   # per-step frames over the first 0.6 s: where a 1e-6 change of v_m first jumps (BDF2)
  for i in bdf2 implicit; do
    r loc s_start.toml $i 100 1.25e-4 --set time.duration=0.6 --set output.interval=1.25e-4
    r locpvm s_start.toml $i 100 1.25e-4 --set time.duration=0.6 --set output.interval=1.25e-4 --set gait.speed=0.28000028
  done ;;
variants)   # (a) no friction, (b) no lift (planar couples; serpenoid), (d) isotropic friction
  # v: each variant at three steps, both integrators, and once more with v_m + 1e-6 (relative)
  v() { local label=$1 file=$2; shift 2
    for dt in 5e-4 2.5e-4 1.25e-4; do for i in implicit bdf2; do r $label $file $i 100 $dt "$@"; done; done
    for i in implicit bdf2; do r ${label}-pvm $file $i 100 1.25e-4 "$@" --set gait.speed=$(python3 -c "import tomllib;print(tomllib.load(open('$file','rb'))['gait']['speed']*(1+1e-6))"); done; }
  v nofric s_start.toml --set ground.mu_forward=1e-6 --set ground.mu_backward=1e-6 --set ground.mu_sideways=1e-6
  v iso s_start.toml --set ground.mu_forward=0.7 --set ground.mu_backward=0.7 --set ground.mu_sideways=0.7
  v planar s_start.toml --set 'gait.scales=[1.0,0.0,1.0]'
  v serp serpenoid.toml ;;
ctol)   # the threshold of BDF2's event rule (contact_tolerance * a) moved; IE uses it only for stick tests
  for c in 1e-8 1e-7; do for i in implicit bdf2; do r ctol$c s_start.toml $i 100 1.25e-4 --set solver.contact_tolerance=$c; done; done ;;
ens)    # the spread under relative changes of v_m of k * 1e-6 (k = -2, -1, 2, 3; k = 0, 1 are base and pvm)
  for dt in 2.5e-4 1.25e-4; do for i in implicit bdf2; do for k in -2 -1 2 3; do
    r ens$k s_start.toml $i 100 $dt --set gait.speed=$(python3 -c "print(0.28*(1+$k*1e-6))")
  done; done; done ;;
m200)   # the issue's mesh
  for dt in 5e-4 2.5e-4 1.25e-4; do for i in implicit bdf2; do r base s_start.toml $i 200 $dt; done; done
  for dt in 2.5e-4 1.25e-4; do for i in implicit bdf2; do for k in 1 -1; do
    r ens$k s_start.toml $i 200 $dt --set gait.speed=$(python3 -c "print(0.28*(1+$k*1e-6))")
  done; done; done ;;
fine)   # smaller steps: 200 elements at 6.25e-5 s; the BDF2 spread at 100 elements and 6.25e-5 s
  for i in implicit bdf2; do r base s_start.toml $i 200 6.25e-5; done
  r ens1 s_start.toml bdf2 200 6.25e-5 --set gait.speed=$(python3 -c "print(0.28*(1+1e-6))")
  for k in 1 -1 2; do for i in bdf2 implicit; do
    r ens$k s_start.toml $i 100 6.25e-5 --set gait.speed=$(python3 -c "print(0.28*(1+$k*1e-6))")
  done; done ;;
cond)   # conditioning of the model itself (IE): v_m changed by 1e-4 and 1e-3 relative
  for el in 100 200; do for e in -1e-3 -1e-4 1e-4 1e-3; do
    dt=1.25e-4; [ $el = 100 ] && dt=2.5e-4
    r cond$e s_start.toml implicit $el $dt --set gait.speed=$(python3 -c "print(0.28*(1+$e))")
  done; done ;;
iedt)   # IE at 200 elements: intermediate and smaller steps
  for dt in 1e-4 8e-5 3.125e-5; do r base s_start.toml implicit 200 $dt; done ;;
bdf2fine)   # BDF2 at 200 elements and 3.125e-5 s, and once with v_m + 1e-6
  r base s_start.toml bdf2 200 3.125e-5
  r ens1 s_start.toml bdf2 200 3.125e-5 --set gait.speed=$(python3 -c "print(0.28*(1+1e-6))") ;;
slap)   # 200 elements, 1.25e-4 s, frames every 1e-3 s up to 2.05 s: the window where the two part
  for i in implicit bdf2; do r slap s_start.toml $i 200 1.25e-4 --set time.duration=2.05 --set output.interval=1e-3; done
  r slap s_start.toml implicit 200 3.125e-5 --set time.duration=2.05 --set output.interval=1e-3
  r slap s_start.toml bdf2 200 3.125e-5 --set time.duration=2.05 --set output.interval=1e-3 ;;
m50)   # 50 elements: the element-scale modes 16x slower than at 200 elements
  for dt in 1e-3 5e-4 2.5e-4 1.25e-4 6.25e-5 3.125e-5; do for i in implicit bdf2; do r base s_start.toml $i 50 $dt; done; done
  for k in 1 -1; do for i in implicit bdf2; do for dt in 2.5e-4 6.25e-5; do
    r ens$k s_start.toml $i 50 $dt --set gait.speed=$(python3 -c "print(0.28*(1+$k*1e-6))")
  done; done; done ;;
m50fine)   # 50 elements at 1.5625e-5 s
  for i in implicit bdf2; do r base s_start.toml $i 50 1.5625e-5; done ;;
soft)   # axial stiffness / 10 (element-scale axial modes 3.2x slower), 50 elements
  for dt in 2.5e-4 1.25e-4 6.25e-5 3.125e-5 1.5625e-5; do for i in implicit bdf2; do r soft s_start.toml $i 50 $dt --set rod.stretch_stiffness=523.2; done; done ;;
landing)   # candidate test scene: a curved rod thrown onto the ground (lands node by node, slides, sticks)
  for dt in 1e-3 5e-4 2.5e-4 1.25e-4; do for i in implicit bdf2; do r land landing.toml $i 30 $dt; r landh landing.toml $i 30 $dt --set initial.height=0.020000001; done; done ;;
landing2)   # the same, tamer (landing2.toml)
  for dt in 1e-3 5e-4 2.5e-4 1.25e-4 6.25e-5; do for i in implicit bdf2; do r land2 landing2.toml $i 30 $dt; r land2h landing2.toml $i 30 $dt --set initial.height=0.020000001; done; done ;;
damping_landing)   # second session: rod.damping_time (Kelvin-Voigt) on the landing scenes
  for dt in 1e-3 5e-4 2.5e-4 1.25e-4 6.25e-5 3.125e-5 1.5625e-5 7.8125e-6; do for i in implicit bdf2; do
    r land2tau1e-3 landing2.toml $i 30 $dt --set rod.damping_time=1e-3; done; done
  for dt in 3.125e-5 1.5625e-5 7.8125e-6 3.90625e-6; do r land2 landing2.toml implicit 30 $dt; done
  for tau in 0 5e-3; do for dt in 4e-4 2e-4 1e-4 5e-5 2.5e-5; do for i in implicit bdf2; do
    r land3tau$tau landing3.toml $i 30 $dt --set rod.damping_time=$tau
    r land4tau$tau landing4.toml $i 30 $dt --set rod.damping_time=$tau
  done; done; done ;;
damping_s_start)   # the S-start with a damping time of 1 ms
  for el in 100 200; do for dt in 5e-4 2.5e-4 1.25e-4 6.25e-5; do for i in implicit bdf2; do
    r tau1e-3 s_start.toml $i $el $dt --set rod.damping_time=1e-3; done; done; done ;;
damping_5ms)   # the S-start with a damping time of 5 ms
  for el in 100 200; do for dt in 5e-4 2.5e-4 1.25e-4; do for i in implicit bdf2; do
    r tau5e-3 s_start.toml $i $el $dt --set rod.damping_time=5e-3; done; done; done
  for i in implicit bdf2; do r tau5e-3 s_start.toml $i 200 6.25e-5 --set rod.damping_time=5e-3; done
  r tau5e-3_bundled s_start.toml bdf2 100 3.6e-3 --set rod.damping_time=5e-3 ;;
normal_always)   # BDF2 with every normal coordinate implicit Euler: needs SLITHER built with normal_always.patch
  export SLITHER_BDF2_NORMAL=always
  for tau in 0 5e-3; do for dt in 1e-4 5e-5 2.5e-5; do r always_land4tau$tau landing4.toml bdf2 30 $dt --set rod.damping_time=$tau; done; done
  for el in 100 200; do for dt in 2.5e-4 1.25e-4; do r always_tau1e-3 s_start.toml bdf2 $el $dt --set rod.damping_time=1e-3; done; done
  r always_bundled s_start.toml bdf2 100 3.6e-3
  unset SLITHER_BDF2_NORMAL ;;
m200fine)   # 200 elements at 1.5625e-5 s
  for i in implicit bdf2; do r base s_start.toml $i 200 1.5625e-5; done ;;
analyse)   # the analyses quoted in FINDINGS.md (read the trajectories written above)
  python3 jump.py runs/loc_bdf2_100_1.25e-4 runs/locpvm_bdf2_100_1.25e-4 3
  python3 jump.py runs/loc_implicit_100_1.25e-4 runs/locpvm_implicit_100_1.25e-4 3
  python3 predictor.py
  python3 diverge.py runs/base_bdf2_100_1.25e-4 runs/pvm_bdf2_100_1.25e-4 5
  python3 diverge.py runs/base_implicit_100_1.25e-4 runs/pvm_implicit_100_1.25e-4 10
  python3 window.py runs/base_implicit_200_{5e-4,2.5e-4,1.25e-4,1e-4,8e-5,6.25e-5,3.125e-5} runs/base_bdf2_200_{5e-4,2.5e-4,1.25e-4,6.25e-5,3.125e-5} runs/ens1_bdf2_200_{2.5e-4,1.25e-4,6.25e-5,3.125e-5}
  python3 window.py runs/base_implicit_50_{2.5e-4,1.25e-4,6.25e-5,3.125e-5,1.5625e-5} runs/base_bdf2_50_{2.5e-4,1.25e-4,6.25e-5,3.125e-5,1.5625e-5}
  python3 slap2.py ;;
esac
done
