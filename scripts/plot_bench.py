#!/usr/bin/env python3
"""Bar chart of an sgfx-bench JSON file: FPS per effect configuration, one group per size.

usage: python3 scripts/plot_bench.py BENCH.json OUT.png
Needs matplotlib (Debian: python3-matplotlib); draws with the Agg backend (no display).
"""
import json
import sys


def main(argv):
    if len(argv) != 3:
        print("usage: plot_bench.py BENCH.json OUT.png", file=sys.stderr)
        return 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_bench.py: matplotlib is missing (Debian: apt-get install python3-matplotlib)",
              file=sys.stderr)
        return 1
    try:
        with open(argv[1], encoding="utf-8") as f:
            data = json.load(f)
        results = data["results"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        print(f"plot_bench.py: {argv[1]}: {e}", file=sys.stderr)
        return 1

    sizes, effects = [], []
    fps = {}
    for r in results:
        size, eff = r["size"], r["effects"]
        if size not in sizes:
            sizes.append(size)
        if eff not in effects:
            effects.append(eff)
        fps[(size, eff)] = r["fps"] or 0.0

    width = 0.8 / max(1, len(effects))
    fig, ax = plt.subplots(figsize=(max(6.0, 1.2 + 0.35 * len(sizes) * len(effects)), 4.5))
    for k, eff in enumerate(effects):
        xs = [i + (k - (len(effects) - 1) / 2) * width for i in range(len(sizes))]
        ax.bar(xs, [fps.get((s, eff), 0.0) for s in sizes], width, label=eff)
    ax.set_xticks(range(len(sizes)))
    ax.set_xticklabels(sizes)
    ax.set_ylabel("FPS (1000 / median ms)")
    title = f"sgfx-bench: {data.get('scene', '')}"
    renderer = data.get("renderer", "")
    if renderer:
        title += f"\n{renderer} ({data.get('context', '')})"
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, ncol=min(len(effects), 5))
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    try:
        fig.savefig(argv[2], dpi=120)
    except OSError as e:
        print(f"plot_bench.py: {argv[2]}: {e}", file=sys.stderr)
        return 1
    print(f"plot_bench.py: wrote {argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
