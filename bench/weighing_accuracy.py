"""Reproduce the weighing paper's accuracy figures on the load-cell simulator,
then measure settling after a load change of the motion-aware chain.

    python bench/weighing_accuracy.py --json weighing.json [--seeds 25]

The experiment (cell, calibration, disturbances, configurations, settling
criterion) is lab.studies.weighing_accuracy; its docstring states the setup.
This script prints its figures as tables and writes them as JSON."""
import argparse
import json

from pysig.io import atomic_output
from lab.studies.weighing_accuracy import run

NAMES = ("raw", "kalman", "chain", "chain_fixed", "adaptive", "adaptive_fixed", "adaptive_preset",
         "recommended", "recommended_hx711_R")


def f(v, nd=2):
    return "never" if v is None else f"{v:.{nd}f}"


def print_tables(o):
    c = o["calibration"]
    print(f"calibration ({o['seeds']} seeds): sensitivity {c['sensitivity_mv_per_kg_median']:.4f} mV/kg, "
          f"{c['counts_per_kg_median']:.0f} counts/kg, linearity error "
          f"{c['linearity_err_pct_fs_median']:.4f} % FS (worst {c['linearity_err_pct_fs_worst']:.4f})")
    ns = o["noise_setting"]
    print(f"noise setting: vibration {ns['vibration_g_rms']:.4f} g rms ({ns['vibration_kg_rms_at_30kg']:.3f} kg "
          f"at 30 kg), impulses {ns['impulse_rate_hz']}/s of {ns['impulse_amp_kg'] / 2:.0f}..{ns['impulse_amp_kg']:.0f} kg "
          f"({ns['how_chosen']})")
    mb = o["adaptive_motion_band_kg"]
    print(f"adaptive motion band ({mb['rule']}): {mb['floor']:.3f} kg on the floor setting, "
          f"{mb['bench']:.4f} kg on the bench setting")
    nr = o["preset_noise_r_kg2"]
    print(f"{nr['rule']}: {nr['floor']:.4g} kg^2 (floor), "
          f"{nr['bench']:.4g} kg^2 (bench); derived thresholds: " + "; ".join(
              f"{name} {setting}: A0 {v['A0']:.4g} kg, band {v['motion_band']:.4g} kg, lock-out {v['lockout_n']}"
              for name, d in o["preset_thresholds_kg"].items() for setting, v in d.items()))
    print()
    print("30 kg, 20 readings | max error kg (median) | % median | % worst | paper")
    print("--- | --- | --- | --- | ---")
    paper = {"raw": "1.86 kg / 6.2 %", "chain": "0.09 kg / 0.3 %"}
    for n in NAMES:
        print(f"{n} | {o[n + '_max_err_kg_30kg']:.3f} | {o[n + '_max_err_pct_30kg']:.2f} | "
              f"{o[n + '_max_err_pct_30kg_worst']:.2f} | {paper.get(n, '-')}")
    print(f"improvement raw -> chain at 30 kg: {o['improvement_raw_to_chain_30kg']:.1f}x (paper 20x); "
          f"with the 20 readings in the first 20 s after power-up instead: raw "
          f"{o['raw_max_err_pct_30kg_first20s']:.2f} %, kalman {o['kalman_max_err_pct_30kg_first20s']:.2f} %, "
          f"chain {o['chain_max_err_pct_30kg_first20s']:.2f} % "
          f"({o['raw_max_err_pct_30kg_first20s'] / o['chain_max_err_pct_30kg_first20s']:.1f}x)")
    print()
    print("mass kg | " + " | ".join(f"{n} %" for n in NAMES) + "   (median / worst over seeds)")
    print(" | ".join("---" for _ in range(len(NAMES) + 1)))
    for r in o["per_mass"]:
        print(f"{r['mass_kg']:.0f} | " + " | ".join(
            f"{r[n + '_max_err_pct_median']:.2f} / {r[n + '_max_err_pct_worst']:.2f}" for n in NAMES))
    print("over the calibrated 10-50 kg (max over masses, median / worst over seeds): " + ", ".join(
        f"{n} {o[n + '_max_err_pct_10to50kg']:.2f} / {o[n + '_max_err_pct_10to50kg_worst']:.2f} %" for n in NAMES))
    print(f"all masses: kalman {o['kalman_max_err_pct_all']:.2f} % (worst {o['kalman_max_err_pct_all_worst']:.2f}), "
          f"chain {o['chain_max_err_pct_all']:.2f} % (worst {o['chain_max_err_pct_all_worst']:.2f}), "
          f"adaptive {o['adaptive_max_err_pct_all']:.2f} % (worst {o['adaptive_max_err_pct_all_worst']:.2f}); "
          f"kalman -> chain {o['improvement_kalman_to_chain_all']:.1f}x (paper: 1.8 % -> 0.4 %, 4.5x)")
    print()
    s = o["settle"]
    print(f"settle: {s['criterion']}; 10 samples/s, {o['seeds']} seeds")
    print("configuration | load change | median s | worst s | runs never settled")
    print("--- | --- | --- | --- | ---")
    for n, label in (("chain", "paper chain"), ("chain_lockfix", "paper chain + lock-out fix only")):
        print(f"{label} | {s['paper_step']} | {f(s[n]['median'], 1)} | {f(s[n]['worst'], 1)} | "
              f"{s[n]['never']}/{o['seeds']}")
    for row in s["by_swing"]:
        where = (f"worst of 5 steps {'-'.join(f'{m:g}' for m in s['staircase_kg'])} kg, swing "
                 f"{row['swing_frac'] * 100:g} % of the step (the load itself needs {row['load_itself_s']:.1f} s)")
        for n in ("adaptive", "adaptive_fixed", "adaptive_preset", "recommended"):
            print(f"{n} | {where} | {f(row[n]['median'], 1)} | {f(row[n]['worst'], 1)} | "
                  f"{row[n]['never']}/{o['seeds']}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", help="write the figures here")
    ap.add_argument("--seeds", type=int, default=25, help="seeds per figure (>= 20; default 25)")
    args = ap.parse_args(argv)
    out = run(args.seeds)
    print_tables(out)
    if args.json:
        with atomic_output(args.json) as fh:
            json.dump(out, fh, indent=1)
        print(f"\nwrote {args.json}")


if __name__ == "__main__":
    main()
