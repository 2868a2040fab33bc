"""Collect the JSON-lines logs of bench_simulation.py runs into one JSON with the equal-accuracy summary.

    python benchmarks/collect_simulation.py benchmarks/results/simulation_*.log
"""

import json
import sys
from pathlib import Path

from bench_simulation import OUT, equal_accuracy, plot_results


def main(paths: list[str]) -> None:
    results, summary = {}, {}
    for path in paths:
        rows = [json.loads(line) for line in Path(path).read_text().splitlines() if line.startswith('{"case"')]
        case = Path(path).stem.replace("simulation_", "")
        results[case] = {"rows": rows, "source": Path(path).name}
        for target in (1e-2, 1e-3, 1e-4):
            best = equal_accuracy(rows, target)
            entry = {m: {"rtol": r["rtol"], "time_per_cycle_s": r["time_per_cycle_s"]} for m, r in best.items()}
            if "idas" in best and "scipy-radau" in best:
                entry["radau_over_idas"] = best["scipy-radau"]["time_per_cycle_s"] / best["idas"]["time_per_cycle_s"]
            summary[f"{case}@{target:g}"] = entry
    (OUT / "simulation.json").write_text(json.dumps({"results": results, "equal_accuracy": summary}, indent=2))
    plot_results(results, ("idas", "cvodes", "scipy-radau"), OUT / "simulation.png")
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main(sys.argv[1:])
