"""The sweep's trade-off plot: per setting of the grid and scenario, the mean polygon intrusion
(m^2) against the mean coverage over seeds, the worst seed as a whisker (matplotlib, Agg)."""


def _label(agg, keys):
    return ", ".join(f"{k.split('.')[-1]}={agg[k]}" for k in keys) or "base config"


def plot_tradeoff(path, aggregates, grid):
    """Writes the plot to `path` and returns it, or None when matplotlib is not installed."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    keys = list(grid["grid"])
    scenarios = list(dict.fromkeys(a["scenario"] for a in aggregates))
    fig, axes = plt.subplots(1, len(scenarios), figsize=(5.5 * len(scenarios), 4.5),
                             squeeze=False)
    for ax, scenario in zip(axes[0], scenarios):
        rows = [a for a in aggregates if a["scenario"] == scenario]
        for a in rows:
            x, y = a["coverage_mean"], a["intrusion_m2_mean"]
            ax.errorbar([x], [y], xerr=[[x - a["coverage_worst"]], [0]],
                        yerr=[[0], [a["intrusion_m2_worst"] - y]], fmt="o", capsize=3)
            ax.annotate(_label(a, keys), (x, y), textcoords="offset points", xytext=(4, 4),
                        fontsize=7)
        ax.set_title(f"{scenario} ({rows[0]['seeds']} seeds)")
        ax.set_xlabel("coverage, mean over seeds (whisker: worst seed)")
        ax.set_ylabel("polygon intrusion m$^2$, mean (whisker: worst)")
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    from freespace.sweep import write_whole

    try:
        write_whole(path, lambda f: fig.savefig(f, format="png", dpi=110), mode="wb")
    finally:
        plt.close(fig)
    return path
