#!/usr/bin/python3
"""A queue's results in pandas: a ranking of its variants per condition, and a figure of it.

    salsa run examples/conditions-queue.json --out results/conditions
    /usr/bin/python3 examples/python/analyse.py results/conditions [--metric fraction_found] [--out DIR]

For each cell and condition of the queue, each variant (a behavior and its parameters) gets its mean
of the metric over the repeats, a 95 % t-interval of that mean, its rank (1: the highest mean) and how
often it was the best of its paired repeat (the same seed and world for every variant; a tie shares the
win). Writes ranking.csv and ranking.png into --out (default: the queue's folder) and prints the table.
The paired differences against the queue's reference are salsa's own comparison.csv.
"""

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402
from scipy import stats  # noqa: E402

import salsa  # noqa: E402


def ranking(summary, metric):
    """One row per (cell, condition, variant): n, mean, ci_low, ci_high, rank, best_share."""
    if metric not in summary.columns:
        raise salsa.InputError(f"--metric: {metric} is not a column of the queue's summary.csv "
                               f"(allowed: {', '.join(c for c in summary.columns if pd.api.types.is_float_dtype(summary[c]))})")
    done = summary[summary["status"] == "ok"].copy()
    if "condition" not in done.columns or done["condition"].isna().all():
        done["condition"] = "all"  # a queue without conditions: one ranking per cell
    done["condition"] = done["condition"].astype(str)
    keys = ["cell", "condition"]
    rows = []
    for (cell, condition), tests in done.groupby(keys, sort=False, observed=True):
        # Who was best in each paired repeat (the same seed for every variant of the cell).
        best = tests.groupby("repeat")[metric].transform("max")
        winners = tests[tests[metric] == best]
        share = winners.groupby("variant", observed=True)["repeat"].apply(
            lambda r: sum(1 / (winners["repeat"] == k).sum() for k in r)) / tests["repeat"].nunique()
        for variant, values in tests.groupby("variant", sort=False, observed=True)[metric]:
            n, mean = values.count(), values.mean()
            half = stats.t.ppf(0.975, n - 1) * values.std(ddof=1) / n ** 0.5 if n > 1 else float("nan")
            rows.append({"cell": cell, "condition": condition, "variant": variant, "n": n, "mean": mean,
                         "ci_low": mean - half, "ci_high": mean + half, "best_share": share.get(variant, 0.0)})
    table = pd.DataFrame(rows)
    table["rank"] = table.groupby(keys)["mean"].rank(ascending=False, method="min").astype(int)
    table = table.sort_values(keys + ["rank"], kind="stable").reset_index(drop=True)
    return table[keys + ["rank", "variant", "n", "mean", "ci_low", "ci_high", "best_share"]]


def figure(table, metric, unit, path):
    """Each variant's mean with its 95 % interval, one colour per condition; variants in the order of
    their mean over the conditions, the best at the top."""
    conditions = list(dict.fromkeys(table["condition"]))
    variants = list(table.groupby("variant", sort=False)["mean"].mean().sort_values().index)
    fig, ax = plt.subplots(figsize=(8, 0.5 * len(variants) * max(1, len(conditions) / 2) + 1.5))
    height = 0.7 / len(conditions)
    for k, condition in enumerate(conditions):
        rows = table[table["condition"] == condition].set_index("variant").reindex(variants)
        y = [i - 0.35 + height * (k + 0.5) for i in range(len(variants))]
        ax.errorbar(rows["mean"], y, xerr=[rows["mean"] - rows["ci_low"], rows["ci_high"] - rows["mean"]],
                    fmt="o", capsize=3, label=condition)
    ax.set_yticks(range(len(variants)), variants)
    ax.set_xlabel(f"{metric} ({unit})" if unit else metric)
    ax.grid(axis="x", alpha=0.3)
    ax.set_title("mean and 95 % interval over paired repeats")
    if len(conditions) > 1:
        ax.legend(title="condition")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("queue", help="a queue's output folder (salsa run QUEUE --out FOLDER)")
    parser.add_argument("--metric", default="fraction_found", help="a column of the queue's summary.csv")
    parser.add_argument("--out", help="where ranking.csv and ranking.png go (default: the queue's folder)")
    args = parser.parse_args(argv)
    try:
        result = salsa.load(args.queue)
        if not isinstance(result, salsa.QueueResult):
            raise salsa.InputError(f"{args.queue}: a test's folder (allowed: a queue's output folder)")
        table = ranking(result.summary, args.metric)
    except salsa.InputError as e:
        print(f"analyse.py: {e}", file=sys.stderr)
        return 2
    out = Path(args.out or args.queue)
    out.mkdir(parents=True, exist_ok=True)
    table.to_csv(out / "ranking.csv", index=False)
    figure(table, args.metric, result.summary.attrs["units"].get(args.metric, ""), out / "ranking.png")
    with pd.option_context("display.width", 160, "display.max_colwidth", 40):
        print(table.drop(columns="cell").to_string(index=False, float_format=lambda v: f"{v:.4f}"))
    print(f"analyse.py: {out / 'ranking.csv'}, {out / 'ranking.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
