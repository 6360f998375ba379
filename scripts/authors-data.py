#!/usr/bin/env python3
"""Writes results/authors/*.json: the per-run totals and the summary tables that the authors' own
notebooks (the public repository IsmaelTito/SEC) keep in their stored outputs.

Only numbers are carried over: each value is read from a cell's printed output (the `total reward
[...]` arrays, the styled tables of means, confidence intervals and p values, the table of the
other tasks' means), never recomputed, and each file names the repository, commit, notebook and
cell it came from. No code of the notebooks is run or copied.

    python3 scripts/authors-data.py NOTEBOOKS_DIR COMMIT [--out results/authors]

NOTEBOOKS_DIR holds SEC_exp1_stats.ipynb as it is at COMMIT (for example
`git show COMMIT:notebooks/SEC_exp1_stats.ipynb`); the files are rewritten byte for byte the same
from the same notebook.
"""

import argparse
import html.parser
import json
import re
import sys
from pathlib import Path

REPOSITORY = "IsmaelTito/SEC"
EPISODES = 5000

# The authors' model names -> this project's conditions (src/experiment/presets.rs). The paper's
# "SEC-rwd" of experiment 4 is the notebook's SEC-PRIOR data and the FIFO arm its SEC-FIFO_v2
# (the notebook's integrated table, cell 43, prints those means under those names).
EXP1 = {
    "SEC": "double-t-maze/SEC",
    "NSEC": "double-t-maze/NSEC",
    "MFEC-ae": "double-t-maze/MFEC-ae",
    "MFEC-rp": "double-t-maze/MFEC-rp",
    "DQN": "double-t-maze/DQN",
    "ERLAM": "double-t-maze/ERLAM",
}
EXP4 = {
    "SEC": "forgetting/SEC-none",
    "SEC-PRIOR": "forgetting/SEC-prior",
    "SEC-FIFO_v2": "forgetting/SEC-fifo",
    "NSEC": "forgetting/NSEC-none",
    "NSEC-FIFO": "forgetting/NSEC-fifo",
    "NSEC-RWD": "forgetting/NSEC-rwd",
}
EXP2 = {f"{m}_ltm{n}": f"m{n}/{m}" for m in ("SEC", "NSEC") for n in (125, 250, 500, 1000)}
EXP3 = {
    "default": "value-function/SEC-default",
    "noDist": "value-function/SEC-noDist",
    "noRR": "value-function/SEC-noRR",
    "noGi_new": "value-function/SEC-noGi",
}
TASKS = {
    "Double T-Maze": "double-t-maze",
    "Cylinder": "cylinder",
    "Detour": "detour",
    "Object Permanence": "object-permanence",
}


def text_of(cell):
    """The cell's printed stream output, joined."""
    return "".join("".join(o.get("text", "")) for o in cell.get("outputs", []) if o.get("output_type") == "stream")


class Table(html.parser.HTMLParser):
    """The rows of a pandas Styler table: header cells and data cells as text."""

    def __init__(self):
        super().__init__()
        self.rows, self.row, self.cell = [], None, None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.row = []
        elif tag in ("td", "th") and self.row is not None:
            self.cell = ""

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self.cell is not None:
            self.row.append(self.cell.strip())
            self.cell = None
        elif tag == "tr" and self.row is not None:
            self.rows.append(self.row)
            self.row = None

    def handle_data(self, data):
        if self.cell is not None:
            self.cell += data


def table_of(cell):
    """The styled table a cell displays: its header and its rows as dicts."""
    for o in cell.get("outputs", []):
        h = o.get("data", {}).get("text/html")
        if h:
            t = Table()
            t.feed("".join(h))
            header, rows = t.rows[0], t.rows[1:]
            return [dict(zip(header, r)) for r in rows if len(r) == len(header)]
    raise SystemExit(f"cell has no table: {''.join(cell['source'])[:80]!r}")


def number(s):
    s = s.strip().strip("*_")
    if s in ("N/A", "nan", "None", ""):
        return None
    return float(s)


def arrays(text, label):
    """Every `label [...]` array printed in `text`, in order, as lists of numbers."""
    out = []
    for m in re.finditer(re.escape(label) + r"\s*\[([^\]]*)\]", text):
        out.append([float(x) for x in m.group(1).split()])
    return out


def runs_from(cell_index, cell, names, order):
    """The per-run totals a cell prints, one `total reward [...]` per model in `order`."""
    totals = arrays(text_of(cell), "total reward ")
    if len(totals) != len(order):
        raise SystemExit(f"cell {cell_index}: {len(totals)} arrays for {len(order)} models")
    return [
        {"condition": names[m], "authorsModel": m, "cell": cell_index, "totals": t} for m, t in zip(order, totals)
    ]


def means_from(cell_index, cell, names):
    """The means (with 95 % CI and p values against the table's base model) a styled table shows."""
    rows = table_of(cell)
    base = rows[0]["Model"]
    out = []
    for r in rows:
        entry = {
            "condition": names[r["Model"]],
            "authorsModel": r["Model"],
            "cell": cell_index,
            "mean": number(r["Mean"]),
            "ci95": [number(r["95% CI Lower"]), number(r["95% CI Upper"])],
        }
        p = number(r["p-value"])
        if p is not None:
            entry["versus"] = names[base]
            entry["p"] = p
            entry["pBonferroni"] = number(r["Adjusted p-value (Bonferroni)"])
        out.append(entry)
    return out


def other_tasks(cell_index, cell):
    """The integrated table of experiment 1's means in every task (pandas' text print, wrapped)."""
    text = text_of(cell)
    blocks = [b for b in text.split("\n\n") if b.strip()]
    columns, rows, index = [], {}, {}
    for block in blocks:
        lines = [l.rstrip(" \\") for l in block.splitlines() if l.strip()]
        columns_here = [c for c in lines[0].split() if c != "Task"]
        for line in lines[1:]:
            i, rest = line.split(None, 1)
            task = next((t for t in TASKS if rest.startswith(t)), None)
            if task is not None:  # the first block names the task after the row index
                index[i] = task
                rest = rest[len(task):]
            values = rest.split()
            rows.setdefault(index[i], {}).update(zip(columns_here, (number(v) for v in values)))
        columns += columns_here
    out = []
    for task, values in rows.items():
        for model in columns:
            out.append({"condition": f"{TASKS[task]}/{model}", "authorsModel": model, "cell": cell_index,
                        "mean": values[model]})
    return out


def write(out_dir, name, experiment, commit, notebook, note, runs, means):
    doc = {
        "experiment": experiment,
        "source": {"repository": REPOSITORY, "commit": commit, "notebook": notebook},
        "note": note,
        "episodes": EPISODES,
        "runs": runs,
        "means": means,
    }
    path = out_dir / name
    path.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"{path}: {len(runs)} models with per-run totals, {len(means)} means")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("notebooks")
    ap.add_argument("commit")
    ap.add_argument("--out", default="results/authors")
    a = ap.parse_args()
    if not re.fullmatch(r"[0-9a-f]{40}", a.commit):
        sys.exit(f"commit: '{a.commit}' is not a 40-digit hex commit")
    nb_name = "SEC_exp1_stats.ipynb"
    cells = json.loads((Path(a.notebooks) / nb_name).read_text())["cells"]
    notebook = f"notebooks/{nb_name}"
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    exp1_runs = runs_from(13, cells[13], EXP1, ["MFEC-ae", "MFEC-rp", "SEC", "NSEC", "DQN", "ERLAM"])
    exp1_means = means_from(24, cells[24], EXP1) + [m for m in other_tasks(34, cells[34]) if
                                                     not m["condition"].startswith("double-t-maze/")]
    write(out, "exp1.json", "exp1", a.commit, notebook,
          "Per-run totals over 5000 episodes (R_ep when positive, else 0, summed) in the double T-maze; "
          "means, 95% CIs and Mann-Whitney p values against SEC (Bonferroni over the five); the other "
          "tasks' means from the integrated table.", exp1_runs, exp1_means)
    exp2_means = means_from(27, cells[27], EXP2) + means_from(28, cells[28], EXP2)
    write(out, "exp2.json", "exp2", a.commit, notebook,
          "Means, 95% CIs and p values against m = 1000 of each model; the notebooks keep no per-run totals "
          "of experiment 2.", [], exp2_means)
    write(out, "exp3.json", "exp3", a.commit, notebook,
          "The first ablation table: means, 95% CIs and p values against the default value function; "
          "no per-run totals, and the solo variants' table is not in the stored outputs.", [],
          means_from(30, cells[30], EXP3))
    exp4_order = ["SEC", "SEC-PRIOR", "SEC-FIFO_v2", "NSEC", "NSEC-FIFO", "NSEC-RWD"]
    exp4_runs = runs_from(15, cells[15], EXP4, exp4_order)
    write(out, "exp4.json", "exp4", a.commit, notebook,
          "Per-run totals over 5000 episodes; the paper's SEC-rwd is the notebook's SEC-PRIOR data, its "
          "SEC-fifo the SEC-FIFO_v2 data; NSEC's means with p values against NSEC without forgetting.",
          exp4_runs, means_from(32, cells[32], EXP4))


if __name__ == "__main__":
    main()
