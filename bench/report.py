#!/usr/bin/env python3
"""Turn the raw runs of bench/bench.sh into bench/results/report.md, CSVs and SVG plots.

Usage: python3 bench/report.py [RESULTS_DIR]   (default bench/results)

Reads RESULTS_DIR/{meta.txt,runs.tsv,sections.tsv,notes.txt,calibration.tsv,commands.txt,
primitives.txt,output.tsv}.  Every number written comes from those files, except the published
figures of TR-97-17, which are in PAPER below and always labelled as the paper's; the analysis
section is generated from the run's own numbers.  Prints a summary; the last line is
  bench: pcdm_rsr_8=N pbw_rsr_8=M ratio_8=R pcdm_wall_8=S pbw_wall_8=T pcdm_speedup_model_8=X
         pbw_speedup_model_8=Y [new keys after these, see summary()]
What each figure is (the report says it too):
  mesh s        measured: the program's own mesh_s, the meshing's wall-clock time (a barrier
                after reading and decomposition to the end of meshing, the slowest rank);
  cpu_max s     measured: CPU seconds (getrusage) of the busiest rank over the same span -- a
                LOWER BOUND on the run's time with one core per rank (it leaves out waiting);
  speedup       wall speedup (measured, the headline when the machine has at least as many
                cores as ranks) and the CPU-bound speedup T1/cpu_max_P (an UPPER bound);
  RSRs          as the programs count them (rsr= and their "rsr:" lines by kind), and under the
                other counting conventions of section "Counting conventions".
Standard library only; one entry point, main().
"""
import csv
import math
import os
import statistics
import sys

# ---------------------------------------------------------------------------- the paper's figures
# Chew, Chrisochoides, Sukup, TR-97-17 (1997), section 4; IBM SP2 "thin" nodes, 22K sites / 43K
# triangles, two-to-one imbalanced load.
PAPER = {
    "pbw": {"time": {1: 8.51, 2: 4.38, 4: 2.89, 8: 1.91}, "rsr": {1: 0, 2: 516, 4: 807, 8: 866}},
    "pcdm": {"time": {1: 8.51, 2: 3.59, 4: 2.29, 8: 1.48}, "rsr": {1: 0, 2: 63, 4: 126, 8: 126}},
}
PAPER_OVH = {"comm_pct": 27.0, "undo_pct": 1.0}
PAPER_LAT_US = 29.0     # one-way latency of a 0-byte message (DMCS on the SP2)
PAPER_NULL_RSR_US = 31.0  # null non-threaded RSR
PAPER_BW = 33.6         # MB/s
NPS = [1, 2, 4, 8]
PROG_NAME = {"pbw": "PBW (Parallel Meshing Algorithm, ./pbw)",
             "pcdm": "PCDM (Parallel Constrained Meshing Algorithm, ./pcdm)"}
CONF_NAME = {"imb2": "two-to-one imbalanced (--imbalance 2, the paper's setting)",
             "imb1": "balanced (no --imbalance)",
             "imb2phases": "./pbw --phases (the paper's Figure 1 data-parallel variant), imbalanced",
             "imb2sp2": "imbalanced, network model at the SP2's figures (--net sp2: 29 us, 33.6 MB/s)"}
SPREAD_WARN = 0.20
CPU = "cpu_max_s"


# ---------------------------------------------------------------------------- small helpers
def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return s


def parse_stats(s):
    d = {}
    for tok in (s or "").split():
        if "=" in tok:
            k, v = tok.split("=", 1)
            d[k] = num(v)
    return d


def isnum(v):
    return isinstance(v, (int, float)) and not (isinstance(v, float) and math.isnan(v))


def clean(xs):
    return [x for x in xs if isnum(x)]


def med(xs):
    xs = clean(xs)
    return statistics.median(xs) if xs else None


def lo(xs):
    xs = clean(xs)
    return min(xs) if xs else None


def hi(xs):
    xs = clean(xs)
    return max(xs) if xs else None


def spread(xs):
    """(max - min) / median, None with fewer than two samples."""
    xs = clean(xs)
    if len(xs) < 2 or not statistics.median(xs):
        return None
    return (max(xs) - min(xs)) / statistics.median(xs)


def f(v, nd=2):
    if v is None or not isnum(v):
        return "NA"
    return "%.*f" % (nd, v)


def fi(v):
    return "NA" if v is None or not isnum(v) else "%d" % round(v)


def frange(xs, nd=2, integer=False):
    """'median (min-max)', or the value when there is one sample."""
    vals = clean(xs)
    if not vals:
        return "NA"
    fm = fi if integer else (lambda v: f(v, nd))
    if len(vals) == 1:
        return fm(vals[0])
    return "%s (%s-%s)" % (fm(med(vals)), fm(min(vals)), fm(max(vals)))


def div(a, b):
    if not isnum(a) or not isnum(b) or b == 0:
        return None
    return a / b


def read_kv(path):
    d = {}
    if os.path.exists(path):
        for ln in open(path):
            ln = ln.rstrip("\n")
            if "=" in ln:
                k, v = ln.split("=", 1)
                d.setdefault(k, v)
                if k == "missing":
                    d.setdefault("missing_list", []).append(v)
    return d


def read_lines(path):
    return [ln.rstrip("\n") for ln in open(path)] if os.path.exists(path) else []


def md_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(["---"] * len(header)) + "|"]
    for r in rows:
        out.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(out)


# ---------------------------------------------------------------------------- RSR conventions
def rsr_kinds(r):
    """{kind: count} from the program's "rsr:" line (./pcdm: split), else {"all": rsr}.  Not
    kinds: mpi_msgs (MPI messages) and self (./pbw's RSRs a rank sent itself: no communication,
    not in rsr=)."""
    k = {key[4:]: v for key, v in r["x"].items()
         if key.startswith("rsr.") and key not in ("rsr.mpi_msgs", "rsr.self") and isnum(v)}
    if not k and isnum(r["s"].get("rsr")):
        k = {"split" if r["prog"] == "pcdm" else "all": r["s"]["rsr"]}
    return k


def is_reply(kind):
    return "reply" in kind


def counts(r):
    """The counting conventions of one run: all, requests (replies excluded), unique requests
    (duplicates apart: ./pcdm's ignored split requests), mpi messages."""
    s = r["s"]
    k = rsr_kinds(r)
    allr = s.get("rsr") if isnum(s.get("rsr")) else (sum(k.values()) if k else None)
    rep = sum(v for kk, v in k.items() if is_reply(kk))
    req = allr - rep if isnum(allr) else None
    dup = s.get("ignored") if r["prog"] == "pcdm" and isnum(s.get("ignored")) else 0
    uniq = req - dup if isnum(req) else None
    mpi = s.get("mpi_msgs") if isnum(s.get("mpi_msgs")) else r["x"].get("rsr.mpi_msgs")
    return {"all": allr, "replies": rep, "requests": req, "duplicates": dup, "unique": uniq,
            "mpi": mpi}


CONVENTIONS = [
    ("all", "every RSR as the programs count them (replies, commits, wakes included)"),
    ("requests", "requests only: every RSR kind but replies"),
    ("unique", "requests, duplicates apart: ./pcdm's split requests that found the edge "
               "already split (ignored=) removed; ./pbw has no duplicate requests"),
    ("mpi", "MPI messages (an aggregate of several RSRs to one rank counts once)"),
]


# ---------------------------------------------------------------------------- the context
class Ctx:
    """Everything read from RESULTS_DIR and everything written so far."""

    def __init__(self, R):
        self.R = R
        self.meta = read_kv(os.path.join(R, "meta.txt"))
        self.notes = [n for n in read_lines(os.path.join(R, "notes.txt")) if n.strip()]
        self.sections = [ln.split("\t") for ln in read_lines(os.path.join(R, "sections.tsv")) if ln.strip()]
        self.calib = [ln.split("\t") for ln in read_lines(os.path.join(R, "calibration.tsv")) if ln.strip()]
        self.commands = read_lines(os.path.join(R, "commands.txt"))
        self.runs = load_runs(os.path.join(R, "runs.tsv"))
        self.missing = set(os.path.basename(m) for m in self.meta.get("missing_list", []))
        try:
            self.cores = int(self.meta.get("nproc", "1"))
        except ValueError:
            self.cores = 1
        self.areas = {k: self.meta.get(k) for k in ("area_43k", "area_129k", "area_1m", "area_10m", "area_fig")}
        self.report, self.csvs, self.out = [], [], []
        self.cell = {}      # (section, label, prog, np) -> medians (tables)
        self.conv = {}      # (conf, np) -> {convention: (pbw, pcdm, ratio)}
        self.keys = {}      # extra keys of the last line

    def H(self, s=""):
        self.report.append(s)

    def csv(self, name, header, rows):
        with open(os.path.join(self.R, name), "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            for r in rows:
                w.writerow(["" if c is None else c for c in r])
        self.csvs.append(name)

    def sel(self, section, label=None, prog=None, np_=None, ok=True):
        return [r for r in self.runs if r["section"] == section and
                (label is None or r["label"] == label) and (prog is None or r["prog"] == prog) and
                (np_ is None or r["np"] == np_) and (not ok or r["ok"])]

    def why_missing(self, section, label, prog, np_):
        rs = self.sel(section, label, prog, np_, ok=False)
        return "/".join(sorted(set(r["rc"] for r in rs))) if rs else "not run"

    def headline(self, np_):
        """True when the wall time of np_ ranks is a measurement with a core per rank."""
        return np_ <= self.cores


def load_runs(path):
    runs = []
    if os.path.exists(path):
        with open(path) as fh:
            for row in csv.DictReader(fh, delimiter="\t", quoting=csv.QUOTE_NONE):
                row["np"] = int(row["np"])
                row["s"] = parse_stats(row.get("stats"))
                row["x"] = parse_stats(row.get("extra"))
                row["ok"] = row["rc"] == "0"
                row["ext_s"] = num(row.get("ext_s"))
                row["rss_sum_kb"] = num(row.get("rss_sum_kb"))
                runs.append(row)
    return runs


def vals(rs, key):
    return [r["s"].get(key) for r in rs]


# ---------------------------------------------------------------------------- header
def sec_header(c):
    m = c.meta
    c.H("# PCDM vs PBW: reproduction of TR-97-17 section 4, and beyond")
    c.H()
    c.H("Generated by `%s` on this machine; every number below comes from this run except the "
        "columns and rows marked **paper**, the published figures of Chew, Chrisochoides and Sukup, "
        "*Parallel Constrained Delaunay Meshing*, Cornell TR-97-17 (1997), measured on an 8-node IBM "
        "SP2 with \"thin\" nodes.  The analysis section is generated from this run's numbers."
        % m.get("invocation", "bash bench/bench.sh"))
    c.H()
    c.H(md_table(["", ""], [
        ["date", m.get("date", "NA")], ["git commit", "`%s`" % m.get("commit", "NA")],
        ["mode", "%s (%s repetition(s) at the paper's size, %s at 1M, %s at 10M)" % (
            m.get("mode", "NA"), m.get("reps", "NA"), m.get("big_reps", "NA"), m.get("big10_reps", "NA"))],
        ["machine", "%s, %s cores (nproc), %s, %s memory" % (m.get("host", "?"), m.get("nproc", "?"),
                                                          m.get("cpu", "?"), m.get("mem", "?"))],
        ["kernel", m.get("kernel", "NA")], ["MPI", m.get("mpirun", "NA")], ["compiler", m.get("cc", "NA")],
        ["domain", "`%s`, `-q %s`" % (m.get("domain", "?"), m.get("qdeg", "?"))],
        ["Triangle", m.get("triangle", "not available")]]))
    c.H()
    try:
        l0 = float(m.get("loadavg_start", "0").split()[0])
    except (ValueError, IndexError):
        l0 = 0.0
    c.H("**Machine load**: load average %s at the start, %s at the end.%s" % (
        m.get("loadavg_start", "NA"), m.get("loadavg_end", "NA"),
        (" **The machine was busy with other work when this run started (load %.1f on %d cores): "
         "times are inflated and noisy, and the RSR counts, which depend on message timing, may "
         "differ from an idle machine's.**" % (l0, c.cores)) if l0 > 0.5 * c.cores else ""))
    c.H()
    if c.notes or c.missing:
        c.H("**Problems in this run** (details in the section *Problems* at the end):")
        c.H()
        for n in c.notes:
            c.H("* " + n)
        c.H()


def sec_definitions(c):
    full = [p for p in NPS if c.headline(p)]
    c.H("## What is counted, what is measured, what is bounded")
    c.H()
    c.H("This machine has **%d cores**; `mpirun --oversubscribe` runs more ranks than cores in turn, "
        "so a wall time on more ranks than cores is not the time of a P-core machine.  The bench "
        "detects it (nproc) and says for every rank count which figure is the headline:" % c.cores)
    c.H()
    c.H("* **mesh s** (measured): the program's own `mesh_s`, the meshing's wall-clock time, from a "
        "barrier after reading and decomposition to the end of meshing, the slowest rank (start-up, "
        "reading, decomposition and output are apart: the whole run is `wall_s`).  **Wall "
        "speedup** = median mesh s on 1 rank / median mesh s on P ranks. "
        "It is the **headline** where P <= %d cores (here P = %s) and is marked *oversubscribed* "
        "beyond." % (c.cores, ", ".join(str(p) for p in full) or "none"))
    c.H("* **cpu_max s** (measured, a lower bound): the CPU seconds (user + system, getrusage) of "
        "the busiest rank over the same span.  It leaves out the time a rank waits for replies or "
        "for a core, so it is a **lower bound** on the run's time with one core per rank, not an "
        "estimate of it; **CPU-bound speedup** = the program's median cpu_max on 1 rank / median "
        "cpu_max on P ranks is therefore an **upper bound** on the speedup.  Where P > %d it is the "
        "only parallel figure this machine can give." % c.cores)
    c.H("* **RSRs**: remote service requests as the programs count them (`rsr=`, and their `rsr:` "
        "lines by kind), requests only (replies excluded), duplicates apart, and MPI messages; see "
        "*Counting conventions*.")
    c.H("* **comm s**: the runtime's communication time `comm_s` (rt_stats.comm_s), the same "
        "measure in both programs: flushing packed RSRs to MPI, and the polls that received an RSR "
        "(receiving, unpacking, dispatching), the handlers' own run time and polls that found "
        "nothing excluded; summed over the ranks.  It is wall-clock time: with more ranks than "
        "cores it also holds the time a rank was descheduled inside such a stretch.")
    c.H("* **network model** (`--net LAT_US,MBPS`, `--net sp2` = 29 us, 33.6 MB/s): every message "
        "between ranks is held at its receiver until latency + size/bandwidth after it was sent "
        "(runtime/rt_net.c); it models a slower network on top of this machine's own.")
    c.H("* Nothing in this report is a model of a P-core machine's time; no column is called "
        "modelled.")
    c.H()


# ---------------------------------------------------------------------------- calibration
def sec_calibration(c):
    a = c.areas
    c.H("## Calibration of the area bound")
    c.H()
    c.H("Triangles scale about as 1/area, so a few `./mesh` runs find the `-a` that gives the paper's "
        "size (43K triangles, 22K sites) and the overhead run's size (129.4K triangles); 1M and 10M "
        "are extrapolated from the 129.4K calibration; the triangle counts in the tables are the "
        "ones the runs produced.  The first bound tried is the domain's bounding box area / 5000 "
        "(`bench/poly.py`).")
    c.H()
    crow = [[x[0], x[1], x[2]] for x in c.calib if len(x) >= 3]
    c.H(md_table(["target triangles", "-a tried", "./mesh triangles"], crow) if crow else
        "_No calibration runs (./mesh missing); fixed areas used._")
    c.H()
    c.H("Chosen: 43K: `-a %s`, 129.4K: `-a %s`, 1M: `-a %s`, 10M: `-a %s`, figures: `-a %s`." %
        tuple(a[k] or "NA" for k in ("area_43k", "area_129k", "area_1m", "area_10m", "area_fig")))
    c.H()
    c.csv("calibration.csv", ["target_triangles", "area", "mesh_triangles"], crow)


# ---------------------------------------------------------------------------- Tables 2 and 3
def cell_of(c, section, label, prog, np_, base):
    """Medians and ranges of one table cell; base = the 1-rank cell for speedups (or None)."""
    rs = c.sel(section, label, prog, np_)
    if not rs:
        return None
    cs = [counts(r) for r in rs]
    d = {"n": len(rs), "rs": rs, "wall": vals(rs, "mesh_s"), "cpu": vals(rs, CPU),
         "tris": med(vals(rs, "triangles")), "mina": lo(vals(rs, "min_angle")),
         "comm": vals(rs, "comm_s")}
    for k in ("all", "requests", "unique", "duplicates", "replies", "mpi"):
        d[k] = [x[k] for x in cs]
    d["wall_m"], d["cpu_m"] = med(d["wall"]), med(d["cpu"])
    if base:
        d["wall_sp"] = div(base["wall_m"], d["wall_m"])
        d["cpu_sp"] = div(base["cpu_m"], d["cpu_m"])
    else:
        d["wall_sp"] = d["cpu_sp"] = None
    d["spread"] = spread(d["wall"])
    c.cell[(section, label, prog, np_)] = d
    return d


def sp_text(c, d, np_):
    """The headline speedup of a cell, labelled."""
    if d is None:
        return "NA"
    if c.headline(np_):
        return "**%s** wall" % f(d["wall_sp"])
    return "%s cpu bound (wall %s, oversubscribed)" % (f(d["cpu_sp"]), f(d["wall_sp"]))


def warn(d):
    s = d.get("spread") if d else None
    return (" **spread %d%%**" % round(100 * s)) if s is not None and s > SPREAD_WARN else ""


def sec_table23(c, prog, tabno):
    c.H("## Table %d: %s, at the paper's size" % (tabno, PROG_NAME[prog]))
    c.H()
    c.H("Domain `%s`, `-q %s -a %s` (~43K triangles, the paper's size: a run takes milliseconds, so "
        "launch and fixed costs dominate the times; this table is kept for the RSR counts -- the "
        "1M and 10M tables below are where time means something).  Median of the repetitions "
        "with (min-max)." % (c.meta.get("domain"), c.meta.get("qdeg"), c.areas["area_43k"]))
    c.H()
    header = ["config", "ranks", "triangles", "mesh s", "**paper** s", "cpu_max s (lower bound)",
              "headline speedup", "**paper** speedup", "RSRs (as counted)", "requests", "unique requests",
              "MPI msgs", "**paper** RSRs", "min angle"]
    rows, crows = [], []
    confs = ["imb2", "imb1"] + (["imb2phases"] if prog == "pbw" else []) + ["imb2sp2"]
    for conf in confs:
        base = cell_of(c, "t23", conf, prog, 1, None) or c.cell.get(("t23", "imb2", prog, 1))
        for np_ in NPS:
            paper = conf in ("imb2", "imb2phases", "imb2sp2")
            pt = PAPER[prog]["time"][np_] if paper else None
            pr = PAPER[prog]["rsr"][np_] if paper else None
            psp = PAPER[prog]["time"][1] / pt if pt else None
            d = cell_of(c, "t23", conf, prog, np_, base)
            if d is None:
                if not c.sel("t23", conf, prog, np_, ok=False):
                    continue
                rows.append([conf, np_, "NA (%s)" % c.why_missing("t23", conf, prog, np_)] + ["NA"] * 11)
                continue
            rows.append([conf, np_, fi(d["tris"]), frange(d["wall"], 3) + warn(d), f(pt) if pt else "-",
                         frange(d["cpu"], 3), sp_text(c, d, np_), f(psp) if psp else "-",
                         frange(d["all"], integer=True), frange(d["requests"], integer=True),
                         frange(d["unique"], integer=True), frange(d["mpi"], integer=True),
                         fi(pr) if pr is not None else "-", f(d["mina"])])
            crows.append([conf, np_, d["n"], d["tris"], d["wall_m"], lo(d["wall"]), hi(d["wall"]), pt,
                          d["cpu_m"], lo(d["cpu"]), hi(d["cpu"]), d["wall_sp"], d["cpu_sp"], psp,
                          med(d["all"]), med(d["requests"]), med(d["unique"]), med(d["mpi"]),
                          med(d["comm"]), pr, d["mina"]])
    c.H(md_table(header, rows))
    c.H()
    c.H("Configs: " + "; ".join("`%s` = %s" % (k, CONF_NAME[k]) for k in confs) + ".  The paper gives "
        "the imbalanced case only.  RSRs: *as counted* = the program's `rsr=`; *requests* = every "
        "kind but replies; *unique* = requests less ./pcdm's duplicate split requests; see "
        "*Counting conventions*.  Speedups against the same config's 1-rank run (`imb2sp2`: against "
        "`imb2`).")
    c.H()
    c.csv("table%d_%s.csv" % (tabno, prog),
          ["config", "ranks", "runs", "triangles", "mesh_s_median", "mesh_s_min", "mesh_s_max",
           "paper_time_s", "cpu_max_s_median", "cpu_max_s_min", "cpu_max_s_max", "wall_speedup",
           "cpu_bound_speedup", "paper_speedup", "rsr_median", "requests_median", "unique_median",
           "mpi_msgs_median", "comm_s_median", "paper_rsr", "min_angle_min"], crows)


def sec_tables_big(c):
    sizes = [s for s in ("1m", "10m") if c.sel("t23m", s, ok=False)]
    if not sizes:
        return
    c.H("## Tables 2 and 3 where time means something: 1M and 10M triangles")
    c.H()
    c.H("Imbalanced (`--imbalance 2`, the paper's setting), `-q %s`, `-a %s` (1M) and `-a %s` (10M); "
        "%s / %s repetitions; median (min-max), **spread** flagged where (max-min)/median exceeds "
        "%d%%.  Headline speedup: wall where the ranks have a core each, else the CPU-bound "
        "(upper-bound) speedup, labelled." % (c.meta.get("qdeg"), c.areas["area_1m"], c.areas["area_10m"],
                                             c.meta.get("big_reps", "?"), c.meta.get("big10_reps", "?"),
                                             round(100 * SPREAD_WARN)))
    c.H()
    rows, crows = [], []
    for size in sizes:
        for prog, label in (("pbw", size), ("pbw", size + "_phases"), ("pcdm", size)):
            if not c.sel("t23m", label, prog, ok=False):
                continue
            base = cell_of(c, "t23m", label, prog, 1, None)
            for np_ in NPS:
                d = cell_of(c, "t23m", label, prog, np_, base)
                name = prog + (" --phases" if label.endswith("_phases") else "")
                if d is None:
                    rows.append([size, name, np_, "NA (%s)" % c.why_missing("t23m", label, prog, np_)] + ["NA"] * 7)
                    continue
                rows.append([size, name, np_, fi(d["tris"]), frange(d["wall"], 3) + warn(d),
                             frange(d["cpu"], 3), sp_text(c, d, np_), frange(d["all"], integer=True),
                             frange(d["requests"], integer=True), frange(d["mpi"], integer=True),
                             frange(d["comm"], 3)])
                crows.append([size, name, np_, d["n"], d["tris"], d["wall_m"], lo(d["wall"]), hi(d["wall"]),
                              d["spread"], d["cpu_m"], lo(d["cpu"]), hi(d["cpu"]), d["wall_sp"], d["cpu_sp"],
                              med(d["all"]), med(d["requests"]), med(d["unique"]), med(d["mpi"]), med(d["comm"])])
    c.H(md_table(["size", "program", "ranks", "triangles", "mesh s", "cpu_max s (lower bound)",
                  "headline speedup", "RSRs (as counted)", "requests", "MPI msgs", "comm s (sum)"], rows))
    c.H()
    c.csv("tables23_big.csv", ["size", "program", "ranks", "runs", "triangles", "mesh_s_median", "mesh_s_min",
                               "mesh_s_max", "wall_spread", "cpu_max_s_median", "cpu_max_s_min",
                               "cpu_max_s_max", "wall_speedup", "cpu_bound_speedup", "rsr_median",
                               "requests_median", "unique_median", "mpi_msgs_median", "comm_s_median"], crows)


# ---------------------------------------------------------------------------- RSRs by kind, conventions
def sec_rsr_kinds(c):
    c.H("## RSRs by kind (paper size, imbalanced)")
    c.H()
    c.H("Medians over the repetitions, from each program's `rsr:` line (kinds as the program names "
        "them; a kind whose name contains `reply` is a reply).  ./pcdm's only kind is the split "
        "request, sent to the owner of each side of a split constraint edge; `duplicates` are "
        "those that found the edge already split (its `ignored=`).")
    c.H()
    kinds = {}
    for prog in ("pbw", "pcdm"):
        for np_ in NPS[1:]:
            for r in c.sel("t23", "imb2", prog, np_):
                for k in rsr_kinds(r):
                    kinds.setdefault(prog, [])
                    if k not in kinds[prog]:
                        kinds[prog].append(k)
    rows, crows = [], []
    for prog in ("pbw", "pcdm"):
        for k in kinds.get(prog, []):
            row = [prog, k + (" (a reply)" if is_reply(k) and k != "reply" else "")]
            for np_ in NPS[1:]:
                v = med([rsr_kinds(r).get(k) for r in c.sel("t23", "imb2", prog, np_)])
                row.append(fi(v))
                crows.append([prog, k, np_, v])
            rows.append(row)
        for key, lab in (("duplicates", "duplicates (in the split count)"), ("mpi", "MPI messages")):
            if prog == "pbw" and key == "duplicates":
                continue
            row = [prog, lab]
            for np_ in NPS[1:]:
                v = med([counts(r)[key] for r in c.sel("t23", "imb2", prog, np_)])
                row.append(fi(v))
                crows.append([prog, key, np_, v])
            rows.append(row)
    c.H(md_table(["program", "kind"] + ["P=%d" % p for p in NPS[1:]], rows))
    c.H()
    c.csv("rsr_kinds.csv", ["program", "kind", "ranks", "median"], crows)


def sec_conventions(c):
    c.H("## Counting conventions: PBW / PCDM")
    c.H()
    c.H("The paper's headline: using the CDT cuts communication by a factor of about seven (its "
        "Tables 2 and 3: 516/63, 807/126, 866/126 RSRs).  The paper does not say what it counted. "
        "Ratio of the medians of PBW and PCDM, at the paper's size, under each convention:")
    c.H()
    for name, text in CONVENTIONS:
        c.H("* `%s`: %s;" % (name, text))
    c.H()
    rows, crows = [], []
    for conf in ("imb2", "imb1", "imb2sp2"):
        for np_ in NPS[1:]:
            pb = c.cell.get(("t23", conf, "pbw", np_))
            pc = c.cell.get(("t23", conf, "pcdm", np_))
            if not pb or not pc:
                continue
            pp = div(PAPER["pbw"]["rsr"][np_], PAPER["pcdm"]["rsr"][np_]) if conf != "imb1" else None
            row = [conf, np_]
            for name, _ in CONVENTIONS:
                a, b = med(pb[name]), med(pc[name])
                r = div(a, b)
                c.conv.setdefault((conf, np_), {})[name] = (a, b, r)
                row.append("%s / %s = **%s**" % (fi(a), fi(b), f(r)))
                crows.append([conf, np_, name, a, b, r, pp])
            row.append(f(pp) if pp else "-")
            rows.append(row)
    c.H(md_table(["config", "ranks"] + ["`%s`" % n for n, _ in CONVENTIONS] + ["**paper**"], rows))
    c.H()
    c.csv("rsr_ratio.csv", ["config", "ranks", "convention", "pbw", "pcdm", "ratio", "paper_ratio"], crows)
    # which convention matches the paper best: the smallest mean |log(ours / paper)|, imb2
    score = {}
    for name, _ in CONVENTIONS:
        errs = []
        for np_ in NPS[1:]:
            r = c.conv.get(("imb2", np_), {}).get(name, (None, None, None))[2]
            pp = div(PAPER["pbw"]["rsr"][np_], PAPER["pcdm"]["rsr"][np_])
            if isnum(r) and r > 0 and pp:
                errs.append(abs(math.log(r / pp)))
        if errs:
            score[name] = math.exp(sum(errs) / len(errs))
    c.best = min(score, key=score.get) if score else None
    c.score = score
    if score:
        c.H("**Closest to the paper** (imbalanced, P = 2, 4, 8; geometric mean of the factor between "
            "our ratio and the paper's): " + ", ".join(
                "`%s` %s" % (n, ("**x%.2f**" if n == c.best else "x%.2f") % score[n])
                for n, _ in CONVENTIONS if n in score) + ".")
        c.H()


# ---------------------------------------------------------------------------- communication time
def sec_comm(c):
    c.H("## Communication time, measured the same way in both meshers")
    c.H()
    c.H("`comm_s` summed over the ranks (see the definitions), median of the repetitions, imbalanced. "
        "The ratio of communication time beside the RSR ratios of the same runs.  Where P > %d "
        "cores the figure also holds descheduled time (marked)." % c.cores)
    c.H()
    rows, crows = [], []
    for section, label in (("t23", "imb2"), ("t23m", "1m"), ("t23m", "10m"), ("t23", "imb2sp2")):
        for np_ in NPS[1:]:
            pb = c.cell.get((section, label, "pbw", np_))
            pc = c.cell.get((section, label, "pcdm", np_))
            if not pb or not pc:
                continue
            cb, cp = med(pb["comm"]), med(pc["comm"])
            rr = div(med(pb["all"]), med(pc["all"]))
            rq = div(med(pb["requests"]), med(pc["unique"]))
            rm = div(med(pb["mpi"]), med(pc["mpi"]))
            cr = div(cb, cp)
            size = {"imb2": "43K", "imb2sp2": "43K, --net sp2"}.get(label, label.upper())
            rows.append([size, np_ if c.headline(np_) else "%d (oversubscribed)" % np_, f(cb, 4), f(cp, 4),
                         "**%s**" % f(cr), f(rr), f(rq), f(rm)])
            crows.append([section, label, np_, cb, cp, cr, rr, rq, rm])
            if section == "t23m" and label == "1m" and np_ == 8:
                c.keys["comm_ratio_1m_8"] = f(cr)
    c.H(md_table(["size", "ranks", "PBW comm s", "PCDM comm s", "comm time PBW/PCDM", "RSRs PBW/PCDM",
                  "requests/unique", "MPI msgs PBW/PCDM"], rows) if rows else "_No runs._")
    c.H()
    c.csv("comm.csv", ["section", "label", "ranks", "pbw_comm_s", "pcdm_comm_s", "comm_ratio", "rsr_ratio",
                       "requests_over_unique_ratio", "mpi_ratio"], crows)


# ---------------------------------------------------------------------------- network model
def sec_net(c):
    lats = sorted(set(int(r["label"][3:]) for r in c.runs if r["section"] == "net" and r["label"].startswith("lat")))
    if not lats:
        return
    c.H("## Time against network latency (network model, 1M triangles, imbalanced)")
    c.H()
    c.H("`--net LAT_US,33.6`: every message between ranks held at its receiver until LAT_US "
        "microseconds + its size at 33.6 MB/s after it was sent (29 us = the SP2's DMCS figures). "
        "Latency 0 = the 1M table above.  Wall s median (min-max); in brackets the slowdown against "
        "latency 0 and the median RSRs.%s" % (
            "" if all(c.headline(p) for p in NPS[1:]) else
            "  Runs on more ranks than cores are oversubscribed: their wall time mixes the model's "
            "delays with waiting for a core."))
    c.H()
    rows, crows, series = [], [], {}
    for prog in ("pbw", "pcdm"):
        for np_ in NPS[1:]:
            d0 = c.cell.get(("t23m", "1m", prog, np_))
            w0 = d0["wall_m"] if d0 else None
            row = [prog, np_, (frange(d0["wall"], 3) + warn(d0)) if d0 else "NA"]
            pts = {0: w0}
            any_run = False
            for lat in lats:
                d = cell_of(c, "net", "lat%d" % lat, prog, np_, None)
                if d is None:
                    row.append("NA" if c.sel("net", "lat%d" % lat, prog, np_, ok=False) else "-")
                    continue
                any_run = True
                pts[lat] = d["wall_m"]
                row.append("%s [x%s, %s RSRs]%s" % (frange(d["wall"], 3), f(div(d["wall_m"], w0)),
                                                    fi(med(d["all"])), warn(d)))
                crows.append([prog, np_, lat, d["n"], d["wall_m"], lo(d["wall"]), hi(d["wall"]),
                              div(d["wall_m"], w0), med(d["all"]), med(d["mpi"]), med(d["comm"])])
            if any_run:
                rows.append(row)
                series[(prog, np_)] = pts
    c.H(md_table(["program", "ranks", "latency 0 s"] + ["%d us" % l for l in lats], rows))
    c.H()
    c.csv("net.csv", ["program", "ranks", "latency_us", "runs", "mesh_s_median", "mesh_s_min", "mesh_s_max",
                      "slowdown_vs_latency0", "rsr_median", "mpi_msgs_median", "comm_s_median"], crows)
    if series:
        svg_net(c, series, [0] + lats, os.path.join(c.R, "plot_net.svg"))
        c.H("![wall time against latency](plot_net.svg)")
        c.H()
        sl = {}
        for (prog, np_), pts in series.items():
            if np_ == 8 and 29 in pts:
                sl[prog] = div(pts[29], pts.get(0))
        if sl:
            c.keys["pbw_sp2_slowdown_8"] = f(sl.get("pbw"))
            c.keys["pcdm_sp2_slowdown_8"] = f(sl.get("pcdm"))


def svg_net(c, series, lats, path):
    """Wall time (log y) against latency (categorical x), one line per program and rank count."""
    W, Hh, left, top, pw, ph = 620, 360, 70, 40, 500, 230
    ys = [v for pts in series.values() for v in pts.values() if isnum(v) and v > 0]
    if not ys:
        return
    lmin, lmax = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    if lmax == lmin:
        lmax += 1

    def X(i):
        return left + 30 + (pw - 60) * i / max(1, len(lats) - 1)

    def Y(v):
        return top + ph - ph * (math.log10(v) - lmin) / (lmax - lmin)

    colors = {"pbw": "#d62728", "pcdm": "#1f77b4"}
    dashes = {2: "", 4: "6,3", 8: "2,3"}
    o = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" '
         'font-size="11">' % (W, Hh), '<rect width="100%" height="100%" fill="white"/>',
         '<text x="%d" y="20" text-anchor="middle" font-size="13">wall time against one-way latency '
         '(network model, 33.6 MB/s), this run</text>' % (W // 2),
         '<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#444"/>' % (left, top, pw, ph)]
    for k in range(lmin, lmax + 1):
        o.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (left, Y(10 ** k), left + pw, Y(10 ** k)))
        o.append('<text x="%d" y="%.1f" text-anchor="end">%g s</text>' % (left - 4, Y(10 ** k) + 4, 10.0 ** k))
    for i, lat in enumerate(lats):
        o.append('<text x="%.1f" y="%d" text-anchor="middle">%d us</text>' % (X(i), top + ph + 14, lat))
    li = 0
    for (prog, np_), pts in sorted(series.items()):
        q = [(X(i), Y(pts[lat])) for i, lat in enumerate(lats) if isnum(pts.get(lat)) and pts[lat] > 0]
        da = 'stroke-dasharray="%s"' % dashes.get(np_, "") if dashes.get(np_) else ""
        if len(q) >= 2:
            o.append('<polyline fill="none" stroke="%s" stroke-width="2" %s points="%s"/>' %
                     (colors[prog], da, " ".join("%.1f,%.1f" % p for p in q)))
        ly = top + ph + 34 + 14 * (li // 3)
        lx = left + 170 * (li % 3)
        o.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2" %s/>' %
                 (lx, ly - 4, lx + 24, ly - 4, colors[prog], da))
        o.append('<text x="%d" y="%d">%s, %d ranks</text>' % (lx + 30, ly, prog, np_))
        li += 1
    o.append("</svg>")
    with open(path, "w") as fh:
        fh.write("\n".join(o) + "\n")


# ---------------------------------------------------------------------------- analysis
def sec_analysis(c):
    c.H("## Analysis (generated from this run's numbers)")
    c.H()
    if not c.conv:
        c.H("_No PBW/PCDM pair at the paper's size: nothing to analyse._")
        c.H()
        return
    np_ = max(p for (conf, p) in c.conv if conf == "imb2") if any(k[0] == "imb2" for k in c.conv) else None
    if np_ is None:
        return
    pb = c.cell[("t23", "imb2", "pbw", np_)]
    pc = c.cell[("t23", "imb2", "pcdm", np_)]
    v = {k: (med(pb[k]), med(pc[k])) for k in ("all", "replies", "requests", "duplicates", "unique", "mpi")}
    pp = div(PAPER["pbw"]["rsr"][np_], PAPER["pcdm"]["rsr"][np_])
    r_all = div(v["all"][0], v["all"][1])
    rep_f = div(v["all"][0], v["requests"][0])       # PBW: all / requests
    dup_f = div(v["all"][1], v["unique"][1])         # PCDM: all / unique
    proto = div(v["requests"][0], v["unique"][1])    # requests / unique requests
    c.H("**What is counted.** At %d ranks (imbalanced, paper size) ./pbw counted %s RSRs, of which %s "
        "(%s%%) are replies; ./pcdm counted %s split requests, of which %s (%s%%) were duplicates "
        "(the edge was already split when the request arrived).  As counted, the ratio is **%s** "
        "against the paper's %s." % (
            np_, fi(v["all"][0]), fi(v["replies"][0]), f(100 * (div(v["replies"][0], v["all"][0]) or 0), 0),
            fi(v["all"][1]), fi(v["duplicates"][1]), f(100 * (div(v["duplicates"][1], v["all"][1]) or 0), 0),
            f(r_all), f(pp)))
    c.H()
    kinds = {k: med([rsr_kinds(r).get(k) for r in pb["rs"]]) for k in rsr_kinds(pb["rs"][0])}
    top = sorted(((x, k) for k, x in kinds.items() if isnum(x) and not is_reply(k)), reverse=True)
    if top and isnum(v["requests"][0]) and v["requests"][0] > 0:
        c.H("**Where PBW's requests come from** (its kinds, median): " + ", ".join(
            "%s %s (%s%%)" % (k, fi(x), f(100 * x / v["requests"][0], 0)) for x, k in top) + ".")
        c.H()
    c.H("**The ratio as a product.** RSRs as counted PBW/PCDM = (PBW requests / PCDM unique requests) "
        "x (PBW all / PBW requests: replies) / (PCDM all / PCDM unique: duplicates) = %s x %s / %s = "
        "%s.  The first factor is what the two protocols need per interface event and how many "
        "interface events each makes; the second is PBW's replies; the third PCDM's duplicates." % (
            f(proto), f(rep_f), f(dup_f), f(div(div((proto or 0) * (rep_f or 0), dup_f), 1))))
    c.H()
    ie = med([r["x"].get("cavities.iface_edges") for r in pb["rs"]])
    il = med([r["x"].get("cavities.iface_len") for r in pb["rs"]])
    if isnum(ie) and ie > 0:
        c.H("**Interface.** ./pbw reports %s edges (length %s) on rank boundaries of its final mesh; "
            "both meshers cut the domain with the same decomposition (par_load), so the interface is "
            "taken to be the same for ./pcdm (which does not report its own).  Per interface edge: "
            "PBW %s requests, PCDM %s unique split requests: the interface is common to both, so the "
            "ratio does not come from interface length but from what each protocol sends per "
            "interface event (PBW: expansions, commits, releases and wakes for every remote cavity; "
            "PCDM: one message per split of an interface subsegment, to the other side)." % (
                fi(ie), f(il, 3), f(div(v["requests"][0], ie)), f(div(v["unique"][1], ie))))
        c.H()
    if c.best:
        b = c.conv.get(("imb2", np_), {}).get(c.best, (None, None, None))
        why = {"all": "counting every message each program sends, replies included, as a transport "
                      "layer's message counter would",
               "requests": "counting requests only: a DMCS RSR counter that leaves the replies out",
               "unique": "counting only the requests that change the mesh (PCDM's duplicates removed)",
               "mpi": "counting network messages, several RSRs to one rank packed in one"}[c.best]
        c.H("**Which convention matches the paper.** `%s` (ratio %s at %d ranks, paper %s; %s off on "
            "average over P = 2, 4, 8): %s.  The others are off by %s." % (
                c.best, f(b[2]), np_, f(pp), "x%.2f" % c.score[c.best], why,
                ", ".join("`%s` x%.2f" % (n, s) for n, s in c.score.items() if n != c.best)))
        c.H()
    lo_r = min((x[2] for x in c.conv.get(("imb2", np_), {}).values() if isnum(x[2])), default=None)
    hi_r = max((x[2] for x in c.conv.get(("imb2", np_), {}).values() if isnum(x[2])), default=None)
    if isnum(lo_r):
        if lo_r <= 1:
            verdict = "The claim does not hold under every convention in this run."
        elif lo_r <= pp <= hi_r:
            verdict = ("The claim that the CDT cuts communication holds here; its size depends on "
                       "what is counted, and the paper's factor of about seven is within the range "
                       "of our conventions.")
        else:
            verdict = ("The claim that the CDT cuts communication holds, by %s than the paper's "
                       "factor of about seven under every convention: what our PBW sends per remote "
                       "cavity (the kinds above) and our PCDM per interface split differ from what "
                       "the paper's implementations sent, which it does not detail."
                       % ("more" if lo_r > pp else "less"))
        c.H("**The paper's claim.** PBW/PCDM is between %s and %s at %d ranks under our conventions "
            "(paper: %s).  %s" % (f(lo_r), f(hi_r), np_, f(pp), verdict))
        c.H()


# ---------------------------------------------------------------------------- plots vs ranks
def svg_plot(c, conf, path):
    """Three panels against ranks: RSRs (log y), time (log y), speedup (linear, with ideal)."""
    pw, ph, gap, left, top = 250, 230, 80, 70, 50
    W, Hh = left + 3 * pw + 2 * gap + 20, top + ph + 170
    colors = {"pbw": "#d62728", "pcdm": "#1f77b4"}
    p_sp = {p: {n: PAPER[p]["time"][1] / PAPER[p]["time"][n] for n in NPS} for p in PAPER}
    s_rsr, s_time, s_sp = [], [], []
    for prog in ("pbw", "pcdm"):
        def g(key, prog=prog):
            out = {}
            for n in NPS:
                d = c.cell.get(("t23", conf, prog, n))
                if d:
                    x = d.get(key)
                    out[n] = med(x) if isinstance(x, list) else x
            return out
        s_rsr.append(("%s RSRs, this run" % prog, colors[prog], "", g("all")))
        s_time.append(("%s cpu_max (lower bound)" % prog, colors[prog], "", g("cpu_m")))
        s_time.append(("%s wall on %d cores" % (prog, c.cores), colors[prog], "2,3", g("wall_m")))
        s_sp.append(("%s CPU-bound speedup (upper bound)" % prog, colors[prog], "", g("cpu_sp")))
        s_sp.append(("%s wall speedup" % prog, colors[prog], "2,3", g("wall_sp")))
        if conf == "imb2":
            s_rsr.append(("%s RSRs, paper" % prog, colors[prog], "8,4", PAPER[prog]["rsr"]))
            s_time.append(("%s time, paper (SP2)" % prog, colors[prog], "8,4", PAPER[prog]["time"]))
            s_sp.append(("%s speedup, paper" % prog, colors[prog], "8,4", p_sp[prog]))
    s_sp.append(("ideal", "#888", "1,4", {n: float(n) for n in NPS}))
    panels = [("RSR count (log; 0 not drawn)", True, s_rsr), ("time, s (log)", True, s_time),
              ("speedup vs 1 rank", False, s_sp)]
    o = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
         'font-family="sans-serif" font-size="11">' % (W, Hh, W, Hh),
         '<rect width="100%" height="100%" fill="white"/>',
         '<text x="%d" y="20" text-anchor="middle" font-size="14">PBW vs PCDM on %s, -q %s -a %s, %s: '
         'this run vs the paper</text>' % (W // 2, c.meta.get("domain", ""), c.meta.get("qdeg", ""),
                                           c.areas["area_43k"], {"imb2": "2:1 imbalanced",
                                                                 "imb1": "balanced"}[conf])]
    for pi, (ylabel, logy, series) in enumerate(panels):
        x0, y0 = left + pi * (pw + gap), top
        ys = [v for _, _, _, sr in series for v in sr.values() if isnum(v) and (v > 0 or not logy)]
        if logy:
            ys = ys or [1.0, 10.0]
            lmin, lmax = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
            lmax = lmax + 1 if lmax == lmin else lmax
            ticks = [10.0 ** k for k in range(lmin, lmax + 1)]

            def Y(v, lmin=lmin, lmax=lmax, y0=y0):
                return y0 + ph - ph * (math.log10(v) - lmin) / (lmax - lmin)
        else:
            ymax = max(ys + [1.0]) * 1.1
            mag = 10 ** math.floor(math.log10(ymax))
            for m in (1, 2, 2.5, 5, 10):
                if m * mag >= ymax:
                    ymax = m * mag
                    break
            ticks = [ymax * k / 5 for k in range(6)]

            def Y(v, ymax=ymax, y0=y0):
                return y0 + ph - ph * v / ymax

        def X(n, x0=x0):
            return x0 + 25 + (pw - 50) * (math.log2(n) / 3.0)

        o.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#444"/>' % (x0, y0, pw, ph))
        for t in ticks:
            o.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (x0, Y(t), x0 + pw, Y(t)))
            o.append('<text x="%d" y="%.1f" text-anchor="end">%s</text>' % (x0 - 4, Y(t) + 4, "%g" % round(t, 4)))
        for n in NPS:
            o.append('<text x="%.1f" y="%d" text-anchor="middle">%d</text>' % (X(n), y0 + ph + 14, n))
        o.append('<text x="%d" y="%d" text-anchor="middle">ranks</text>' % (x0 + pw // 2, y0 + ph + 28))
        o.append('<text x="%d" y="%d" text-anchor="middle" transform="rotate(-90 %d %d)">%s</text>' %
                 (x0 - 45, y0 + ph // 2, x0 - 45, y0 + ph // 2, ylabel))
        for li, (lab, col, dash, sr) in enumerate(series):
            pts = [(X(n), Y(sr[n])) for n in NPS if isnum(sr.get(n)) and (sr[n] > 0 or not logy)]
            da = ('stroke-dasharray="%s"' % dash) if dash else ""
            if len(pts) >= 2:
                o.append('<polyline fill="none" stroke="%s" stroke-width="2" %s points="%s"/>' %
                         (col, da, " ".join("%.1f,%.1f" % q for q in pts)))
            for q in pts:
                o.append('<circle cx="%.1f" cy="%.1f" r="2.5" fill="%s"/>' % (q[0], q[1], col))
            ly = y0 + ph + 48 + 14 * li
            o.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2" %s/>' %
                     (x0, ly - 4, x0 + 24, ly - 4, col, da))
            o.append('<text x="%d" y="%d">%s</text>' % (x0 + 30, ly, lab))
    o.append("</svg>")
    with open(path, "w") as fh:
        fh.write("\n".join(o) + "\n")


def sec_plots(c):
    c.H("## Plot: RSRs and time against ranks (paper size)")
    c.H()
    for conf in ("imb2", "imb1"):
        name = "plot_%s.svg" % conf
        svg_plot(c, conf, os.path.join(c.R, name))
        c.H("%s: [%s](%s)" % (CONF_NAME[conf], name, name))
        c.H()
        c.H("![RSRs and time vs ranks, %s](%s)" % (conf, name))
        c.H()
    c.H("Solid: this run's RSRs, cpu_max (a lower bound on time) and CPU-bound speedup (an upper "
        "bound).  Dotted: this run's wall time and wall speedup on this machine's %d cores.  Dashed: "
        "the paper's published figures (SP2; imbalanced plot only)." % c.cores)
    c.H()


# ---------------------------------------------------------------------------- overhead
def sec_overhead(c):
    c.H("## PBW overhead breakdown (paper: 4 processors, 65.5K sites, 129.4K triangles)")
    c.H()
    c.H("Paper: communication overhead about 27%%, undo-computation overhead about 1%%.  Ours: "
        "`comm_pct` and `undo_pct` from `./pbw --stats` on 4 ranks at `-a %s` (~129.4K triangles): "
        "comm_pct = 100 x (handler + comm) / (busy + comm), with comm the runtime's `comm_s` (empty "
        "polls excluded); median (min-max); ./pcdm on the same input beside it." % c.areas["area_129k"])
    c.H()
    rows, crows = [], []
    for conf in ("imb2", "imb1"):
        for prog in ("pbw", "pcdm"):
            rs = c.sel("ovh", conf, prog, 4)
            if not rs:
                if c.sel("ovh", conf, prog, 4, ok=False):
                    rows.append([conf, prog, "NA (%s)" % c.why_missing("ovh", conf, prog, 4)] + ["NA"] * 8)
                continue
            cp, up = vals(rs, "comm_pct"), vals(rs, "undo_pct")
            rows.append([conf, prog, fi(med(vals(rs, "triangles"))), frange(vals(rs, "mesh_s"), 3),
                         frange(vals(rs, CPU), 3), frange(vals(rs, "rsr"), integer=True),
                         frange(vals(rs, "comm_s"), 4),
                         frange(vals(rs, "undone"), integer=True) if prog == "pbw" else "-",
                         frange(cp, 1) if prog == "pbw" else "-", frange(up, 1) if prog == "pbw" else "-",
                         "27 / 1" if prog == "pbw" else "-"])
            crows.append([conf, prog, 4, len(rs), med(vals(rs, "triangles")), med(vals(rs, "mesh_s")),
                          med(vals(rs, CPU)), med(vals(rs, "rsr")), med(vals(rs, "comm_s")),
                          med(vals(rs, "undone")), med(cp), lo(cp), hi(cp), med(up), lo(up), hi(up),
                          PAPER_OVH["comm_pct"] if prog == "pbw" else None,
                          PAPER_OVH["undo_pct"] if prog == "pbw" else None])
    c.H(md_table(["config", "program", "triangles", "mesh s", "cpu_max s", "RSRs", "comm s (sum)", "undone",
                  "comm %", "undo %", "**paper** comm % / undo %"], rows))
    c.H()
    c.csv("overhead.csv", ["config", "program", "ranks", "runs", "triangles", "mesh_s", "cpu_max_s", "rsr",
                           "comm_s", "undone", "comm_pct_median", "comm_pct_min", "comm_pct_max",
                           "undo_pct_median", "undo_pct_min", "undo_pct_max", "paper_comm_pct",
                           "paper_undo_pct"], crows)
    for r in crows:
        if r[1] == "pbw":
            c.out.append("Overhead pbw P=4 %s: comm_pct=%s undo_pct=%s   [paper 27 / 1]" % (r[0], f(r[10], 1), f(r[13], 1)))


# ---------------------------------------------------------------------------- issue 16
def sec_balance(c):
    c.H("## Beyond the paper: dynamic load balancing and determinism (issue 16)")
    c.H()
    c.H("./pcdm at `-a %s` (~1M triangles), %s repetitions, medians.  *balanced*: no `--imbalance`; "
        "*static*: `--imbalance 2`, one subdomain per rank (rank 0 gets twice the work); *dynamic*: "
        "`--imbalance 2 --balance dynamic` (4 subdomains per rank; an idle rank takes unstarted ones "
        "from a busy rank).  mesh s = measured wall time of the meshing (`mesh_s`); CPU-bound speedup "
        "= cpu_sum / cpu_max (the busiest rank's CPU seconds: what a core per rank would bound); "
        "vs balanced = the balanced run's figure over this one's (wall: goal <= 1.1x at 2 ranks; CPU "
        "speedup: goal >= 90%% at 8); moves = migrations, move %% = move_max_s / mesh_s (goal <= 2%%)."
        % (c.areas["area_1m"], max([int(r["rep"]) for r in c.sel("bal", ok=False)] or [0])))
    c.H()
    rows, crows = [], []
    for np_ in (2, 8):
        base = c.sel("bal", "static", "pcdm", np_)
        bw = med(vals(base, "mesh_s"))
        bsp = med([div(r["s"].get("cpu_sum_s"), r["s"].get(CPU)) for r in base])
        for lab in ("static", "imb2static", "imb2dynamic"):
            rs = c.sel("bal", lab, "pcdm", np_)
            if not rs:
                rows.append([np_, lab, "NA (%s)" % c.why_missing("bal", lab, "pcdm", np_)] + ["NA"] * 7)
                continue
            w = med(vals(rs, "mesh_s"))
            sp = med([div(r["s"].get("cpu_sum_s"), r["s"].get(CPU)) for r in rs])
            mig = med(vals(rs, "migrations"))
            mv = med([div(r["s"].get("move_max_s"), r["s"].get("mesh_s")) for r in rs])
            rows.append([np_, lab, fi(med(vals(rs, "triangles"))), frange(vals(rs, "mesh_s"), 3),
                         f(div(w, bw)), f(sp), f(div(sp, bsp)), fi(mig) if isnum(mig) else "-",
                         f(100 * mv, 3) if isnum(mv) else "-", warn({"spread": spread(vals(rs, "mesh_s"))}) or "-"])
            crows.append([np_, lab, len(rs), med(vals(rs, "triangles")), w, div(w, bw), sp, div(sp, bsp),
                          mig, mv])
            if lab == "imb2dynamic":
                c.out.append("Balance P=%d dynamic vs balanced: wall %s x (goal <= 1.1 at P=2), CPU-bound "
                             "speedup %s of balanced (goal >= 0.90 at P=8), move %s%% of wall" %
                             (np_, f(div(w, bw)), f(div(sp, bsp)), f(100 * mv, 3) if isnum(mv) else "NA"))
                c.keys["dyn_wall_vs_balanced_%d" % np_] = f(div(w, bw))
                c.keys["dyn_cpu_speedup_vs_balanced_%d" % np_] = f(div(sp, bsp))
    c.H(md_table(["ranks", "config", "triangles", "mesh s", "wall / balanced", "CPU-bound speedup",
                  "speedup / balanced", "moves", "move %", "spread"], rows))
    c.H()
    c.csv("balance.csv", ["ranks", "config", "runs", "triangles", "mesh_s", "wall_vs_balanced",
                          "cpu_bound_speedup", "speedup_vs_balanced", "migrations", "move_fraction"], crows)
    da, dd = c.sel("det", "async", "pcdm", 2), c.sel("det", "deterministic", "pcdm", 2)
    area = (da or dd or [{"area": "NA"}])[0]["area"]
    c.H("`--deterministic` against the asynchronous mode, 2 ranks, `-a %s`: mesh s and the busiest "
        "rank's CPU seconds, median (min-max); goal <= 1.15x; hashes must agree between the "
        "deterministic runs." % area)
    c.H()
    if da and dd:
        wa, wd = med(vals(da, "mesh_s")), med(vals(dd, "mesh_s"))
        ca, cd = med(vals(da, CPU)), med(vals(dd, CPU))
        hashes = sorted(set(str(r["s"].get("hash")) for r in dd))
        c.H(md_table(["mode", "triangles", "mesh s", "cpu_max s", "rounds", "hash"],
                     [["async", fi(med(vals(da, "triangles"))), frange(vals(da, "mesh_s"), 3),
                       frange(vals(da, CPU), 3), "-", "differs run to run"],
                      ["deterministic", fi(med(vals(dd, "triangles"))), frange(vals(dd, "mesh_s"), 3),
                       frange(vals(dd, CPU), 3), fi(med(vals(dd, "rounds"))),
                       hashes[0] if len(hashes) == 1 else "DIFFER: " + " ".join(hashes)]]))
        c.H()
        c.H("Deterministic / asynchronous: wall %s x, cpu_max %s x." % (f(div(wd, wa)), f(div(cd, ca))))
        c.out.append("Determinism cost (2 ranks, -a %s): wall %s x, cpu_max %s x (goal <= 1.15); %s" % (
            area, f(div(wd, wa)), f(div(cd, ca)),
            "one hash" if len(hashes) == 1 else "HASHES DIFFER"))
        c.keys["det_cost_wall"] = f(div(wd, wa))
    else:
        c.H("_No determinism runs (%s / %s)._" % (c.why_missing("det", "async", "pcdm", 2),
                                                  c.why_missing("det", "deterministic", "pcdm", 2)))
    c.H()


# ---------------------------------------------------------------------------- primitives
def sec_primitives(c):
    R = c.R
    c.H("## Primitive costs (`bash bench/primitives.sh`, 2 ranks), like with like")
    c.H()
    ptxt = read_lines(os.path.join(R, "primitives.txt"))
    prc = (read_lines(os.path.join(R, "primitives.rc")) or ["rc=?"])[0]
    pline = [ln for ln in ptxt if ln.startswith("primitives:")]
    p = parse_stats(pline[-1][len("primitives:"):]) if pline else {}
    nt, raw, bw = p.get("null_rsr_us"), p.get("raw_mpi_roundtrip_us"), p.get("bandwidth_MBps")
    rows = [
        ["one-way latency, 0 bytes", "raw MPI RTT/2: %s us" % f(div(raw, 2)), "%s us" % f(PAPER_LAT_US, 0),
         "one-way beside one-way"],
        ["null non-threaded RSR, one way", "RSR RTT/2: %s us" % f(div(nt, 2)), "%s us" % f(PAPER_NULL_RSR_US, 0),
         "the paper's 31 us is most likely one-way: 2 us above its 29 us one-way latency, far "
         "below a round trip (58 us)"],
        ["null non-threaded RSR, round trip", "%s us" % f(nt), "(%s us if one-way x 2)" % f(2 * PAPER_NULL_RSR_US, 0),
         "round trip beside round trip"],
        ["raw MPI 0-byte round trip", "%s us" % f(raw), "(%s us: 2 x 29)" % f(2 * PAPER_LAT_US, 0), "round trip"],
        ["null RSR round trip / raw MPI round trip", "**%s** (goal <= 1.30: %s)" % (
            f(p.get("ratio")), "met" if isnum(p.get("ratio")) and p["ratio"] <= 1.30 else "NOT met"),
         "%s (31 / 29, both one-way)" % f(PAPER_NULL_RSR_US / PAPER_LAT_US), "the runtime's overhead on MPI"],
        ["peak bandwidth, 1 MB payloads", "%s MB/s" % f(bw, 1), "%s MB/s" % f(PAPER_BW, 1), ""],
    ]
    # the threads module: the paper's thread creation (12 us) and context switch (5.5 us); goal:
    # ours within 2x
    for key, what, paper, note in (
            ("thread_start_us", "threaded null RSR to self (a pooled worker runs it)", 12.0,
             "DMCS created a thread per threaded RSR: thread creation"),
            ("worker_task_us", "a worker's task, start to end (./pcdm --threads' round dispatch)", 12.0,
             "threaded RSR to self + non-threaded RSR back to the main thread"),
            ("context_switch_us", "context switch (a task waits for a reply and resumes)", 5.5,
             "the raw pthread condvar switch is in the output below")):
        v = p.get(key)
        rows.append([what, "%s us (goal <= %s: %s)" % (f(v), f(2 * paper, 0), "met" if isnum(v) and v <= 2 * paper
                                                        else "NOT met"), "%s us" % f(paper, 1), note])
    rows.append(["threaded null RSR round trip, 2 ranks", "%s us" % f(p.get("threaded_rsr_us")), "-",
                 "the reply sent by a worker"])
    c.H(md_table(["primitive", "this run (best of interleaved trials)", "**paper** (SP2, DMCS)", "note"], rows))
    c.H()
    c.keys["null_rsr_ratio"] = f(p.get("ratio"))
    c.csv("primitives.csv", ["key", "this_run", "paper"],
          [["one_way_latency_us", div(raw, 2), PAPER_LAT_US], ["null_rsr_one_way_us", div(nt, 2), PAPER_NULL_RSR_US],
           ["null_rsr_roundtrip_us", nt, None], ["raw_mpi_roundtrip_us", raw, 2 * PAPER_LAT_US],
           ["ratio", p.get("ratio"), PAPER_NULL_RSR_US / PAPER_LAT_US], ["threaded_rsr_us", p.get("threaded_rsr_us"), None],
           ["bandwidth_MBps", bw, PAPER_BW], ["thread_start_us", p.get("thread_start_us"), 12.0],
           ["worker_task_us", p.get("worker_task_us"), 12.0], ["context_switch_us", p.get("context_switch_us"), 5.5]])
    if pline:
        c.H("Runtime and raw MPI trials alternate in the same run (bench/primitives.c).  Output of "
            "`bash bench/primitives.sh`:")
        c.H()
        c.H("```")
        c.H("\n".join(ptxt))
        c.H("```")
    else:
        perr = read_lines(os.path.join(R, "primitives.err"))
        c.H("**bench/primitives.sh produced no `primitives:` line (%s).**%s" % (
            prc, (" Last lines of its stderr:\n\n```\n%s\n```" % "\n".join(perr[-10:])) if perr else ""))
    c.H()


# ---------------------------------------------------------------------------- coastlines at scale
def sec_coast_scale(c):
    txt = read_lines(os.path.join(c.R, "coast_scale.txt"))
    if not txt:
        return
    c.H("## Real coastlines at scale (`bash bench/coast_scale.sh`)")
    c.H()
    c.H("Great Britain and North America (GSHHG, full resolution, projected metres), -q 30, about "
        "10M triangles; each run one whole process measured by the wall clock in this run; "
        "x_mesh = wall / ./mesh's wall; phases from the programs' -V lines (seconds; refine_s of "
        "./mesh: CDT + refinement; of Triangle: its triangulate() call alone); peak_MB: the "
        "largest rank's peak resident size.  Goals: --threads 2 and -np 2 <= 0.6x ./mesh, -np 8 "
        "no slower than -np 2, decomposition <= 5%, triangles within 3%.")
    c.H()
    c.H("```")
    c.H("\n".join(txt))
    c.H("```")
    c.H()


# ---------------------------------------------------------------------------- figures, decomposition
def sec_figures(c):
    c.H("## Figures 1 and 3: meshes coloured by rank")
    c.H()
    c.H("2 ranks, balanced, `-a %s` (a few thousand triangles).  The paper's Figure 1 is a PBW mesh "
        "(one mesh, triangles owned by ranks); Figure 3 a PCDM mesh (subdomains separated by "
        "constraint edges)." % c.areas["area_fig"])
    c.H()
    for prog, fig in (("pbw", "Figure 1 (PBW)"), ("pcdm", "Figure 3 (PCDM)")):
        name = "fig_%s_2ranks.svg" % prog
        rs = c.sel("fig", "small", prog, 2)
        if rs and os.path.exists(os.path.join(c.R, name)):
            s = rs[0]["s"]
            c.H("%s: [%s](%s), %s triangles, %s RSRs" % (fig, name, name, fi(s.get("triangles")), fi(s.get("rsr"))))
            c.H()
            c.H("![%s](%s)" % (fig, name))
        else:
            c.H("%s: not produced (%s)." % (fig, c.why_missing("fig", "small", prog, 2) if not rs else "no SVG written"))
        c.H()


def sec_decomp(c):
    c.H("## The decomposition (issue 11): balance, triangle count, cost")
    c.H()
    c.H("`./pcdm` at 8 ranks with its default subdomains, `-q %s`, beside `./mesh` at the same bounds; "
        "one run each.  balance = the busiest rank's triangles / the mean over the ranks (targets: "
        "<= 1.05 with an area bound, <= 1.10 with the angle bound alone); vs ./mesh = pcdm's "
        "triangles / ./mesh's - 1; decomp s = the slowest rank's seconds in the "
        "decomposition (`decomp_s`); decomp / mesh s = its share of pcdm's `mesh_s`." % c.meta.get("qdeg", "20.7"))
    c.H()
    rows = []
    for lab in sorted(set(r["label"] for r in c.runs if r["section"] == "decomp")):
        pc = c.sel("decomp", lab, "pcdm")
        ms = c.sel("decomp", lab, "mesh", 1)
        if not pc:
            rows.append([lab, "-", "-", "-", "-", "-", "-", "-", "-", c.why_missing("decomp", lab, "pcdm", None)])
            continue
        s = pc[0]["s"]
        mt = ms[0]["s"].get("triangles") if ms else None
        rel = div(s.get("triangles"), mt)
        share = div(s.get("decomp_s"), s.get("mesh_s"))
        ex = s.get("decomp_exact")
        rows.append([lab, "%d" % pc[0]["np"], fi(s.get("subdomains")),
                     "exact" if ex == 1 else "coarse" if ex == 0 else "-", fi(s.get("triangles")), fi(mt),
                     f(div(s.get("tri_max"), s.get("tri_mean")), 3),
                     ("%+.2f%%" % (100 * (rel - 1))) if rel is not None else "-", f(s.get("decomp_s"), 3),
                     ("%.1f%%" % (100 * share)) if isnum(share) else "-"])
    c.H(md_table(["domain / bound", "ranks", "subdomains", "route", "pcdm triangles", "./mesh triangles",
                  "balance", "vs ./mesh", "decomp s", "decomp / mesh s"], rows))
    c.H()
    c.H("route: `exact` = the decomposition was drawn on the exact preview (small final meshes); "
        "`coarse` = the coarse quality mesh weighted by predicted work.  Where ./mesh makes fewer "
        "than 12 triangles per rank the count cannot match: every subdomain needs triangles of its own.")
    c.H()
    for row in rows:
        c.out.append("Decomp %-18s P=%s K=%s %-6s balance %s  vs ./mesh %s  decomp/mesh %s" %
                     (row[0], row[1], row[2], row[3], row[6], row[7], row[9]))


# ---------------------------------------------------------------------------- scale
def sec_scale(c):
    c.H("## Beyond the paper: 1M and 10M triangles against ./mesh and Triangle")
    c.H()
    c.H("Balanced runs; where a size ran several repetitions (alternating the programs), the figures "
        "are medians.  Against the sequential `./mesh` and Shewchuk's Triangle (PyPI "
        "`triangle`, time of the `triangulate` call only, switches `pq%sa<area>Q`).  tri/s = "
        "triangles / mesh s (measured); cpu_max s = the busiest rank's CPU seconds (a lower bound on "
        "the time with a core per rank); CPU-bound speedup = 1-rank cpu_max / cpu_max_P (an upper "
        "bound); vs ./mesh (wall) = ./mesh wall / wall.  Memory = sum over the processes of each "
        "one's peak RSS (`/usr/bin/time -f %%M`; Triangle: the python process's own peak), per "
        "triangle; `own B/tri` is the program's own `bytes_per_tri`." % c.meta.get("qdeg", "20.7"))
    c.H()
    rows, crows = [], []
    for lab in [x for x in ("1m", "10m") if c.sel("scale", x, ok=False)]:
        mesh_wall = med(vals(c.sel("scale", lab, "mesh", 1), "mesh_s"))
        t1 = {p: med(vals(c.sel("scale", lab, p, 1), CPU)) for p in ("pcdm", "pbw")}
        for prog, np_ in [("mesh", 1), ("triangle", 1)] + [(p, n) for p in ("pcdm", "pbw") for n in NPS]:
            all_rs = c.sel("scale", lab, prog, np_, ok=False)
            if not all_rs:
                continue
            rs = [r for r in all_rs if r["ok"]]
            if not rs:
                rows.append([lab, prog, np_, "NA (%s)" % c.why_missing("scale", lab, prog, np_)] + ["NA"] * 10)
                continue
            s = rs[0]["s"]
            par = prog in ("pcdm", "pbw")
            tris, wall = s.get("triangles"), med(vals(rs, "mesh_s"))
            cpu = med(vals(rs, CPU)) if par else None
            rss_kb = rs[0]["rss_sum_kb"] if isnum(rs[0]["rss_sum_kb"]) else None
            if prog == "triangle" and isnum(s.get("peak_rss_mb")):
                rss_kb = s["peak_rss_mb"] * 1024.0
            bpt = div(rss_kb * 1024.0 if rss_kb else None, tris)
            own = s.get("bytes_per_tri") if isnum(s.get("bytes_per_tri")) else None
            csp = div(t1.get(prog), cpu) if par else None
            rsr = med(vals(rs, "rsr")) if par else None
            rows.append([lab, prog, np_, fi(tris), f(wall, 3), f(cpu, 3) if par else "-", fi(div(tris, wall)),
                         f(csp) if csp else "-", f(div(mesh_wall, wall)), f(rss_kb / 1024.0, 0) if rss_kb else "NA",
                         fi(bpt), fi(own) if own else "-", fi(rsr) if rsr is not None else "-",
                         f(div(rsr * 1000.0, tris), 3) if isnum(rsr) else "-"])
            crows.append([lab, prog, np_, tris, s.get("vertices"), wall, cpu, div(tris, wall), csp,
                          div(mesh_wall, wall), rss_kb / 1024.0 if rss_kb else None, bpt, own, rsr,
                          div(rsr * 1000.0, tris) if isnum(rsr) else None, s.get("min_angle"), rs[0]["area"]])
            c.out.append("Scale %-3s %-8s P=%d: %s triangles, %s tri/s wall%s" % (
                lab, prog, np_, fi(tris), fi(div(tris, wall)), (", CPU-bound speedup %s" % f(csp)) if csp else ""))
    if rows:
        c.H(md_table(["size", "program", "ranks", "triangles", "mesh s", "cpu_max s (lower bound)", "tri/s wall",
                      "CPU-bound speedup", "vs ./mesh (wall)", "peak MB (sum)", "B/tri", "own B/tri", "RSRs",
                      "RSRs/1000 tri"], rows))
    else:
        c.H("_No scale runs._")
    c.H()
    c.csv("scale.csv", ["size", "program", "ranks", "triangles", "vertices", "mesh_s", "cpu_max_s",
                        "tri_per_s_wall", "cpu_bound_speedup", "speedup_vs_mesh_wall", "peak_rss_mb_sum",
                        "bytes_per_tri", "own_bytes_per_tri", "rsr", "rsr_per_1000_tri", "min_angle", "area"], crows)


# ---------------------------------------------------------------------------- many segments
COAST_GOAL = 1.5


def sec_coast(c):
    """./pbw against ./pcdm on a real coastline (bench.sh section "coast")."""
    c.H("## Beyond the paper: many segments (a real coastline)")
    c.H()
    path, area = c.meta.get("coast"), c.meta.get("coast_area")
    if not c.sel("coast", ok=False):
        why = "not run"
        if path == "unavailable":
            why = "the coastline is not available in this run (see *Problems*)"
        elif path and not area:
            why = "./mesh could not mesh the coastline (see *Problems*)"
        elif not path:
            why = "section not run (NO_COAST=1, or the bench stopped before it)"
        c.H("_Skipped: %s._" % why)
        c.H()
        c.out.append("Coast: skipped: %s" % why)
        c.keys["coast_ratio_2"] = c.keys["coast_ratio_8"] = "NA"
        return
    c.H("Great Britain from GSHHG at full resolution (`%s`: one polygon of 49,152 vertices in projected "
        "metres, domain area %s m2, written by `bench/coast.py`), `-q 30 -a %s`: a domain with many "
        "segments, where walks of point location meet constraint edges.  %s repetitions, medians (min-max).  mesh s = the program's "
        "`mesh_s`; cpu_max s = the busiest rank's CPU seconds; pbw / pcdm = the ratio of the median wall "
        "times at the same rank count (goal <= %.1f), and of cpu_max; ./mesh's time beside.  %s" % (
            path, "%.3g" % num(c.meta.get("coast_domain_area"))
            if isnum(num(c.meta.get("coast_domain_area"))) else "NA", area,
            max([int(r["rep"]) for r in c.sel("coast", ok=False)] or [0]), COAST_GOAL,
            "8 ranks on %d cores are oversubscribed: their wall times include waiting for a core." % c.cores
            if c.cores < 8 else ""))
    c.H()
    rows, crows = [], []
    mesh_rs = c.sel("coast", "gb", "mesh", 1)
    mw = med(vals(mesh_rs, "mesh_s"))
    rows.append(["./mesh", 1, fi(med(vals(mesh_rs, "triangles"))) if mesh_rs else
                 "NA (%s; see *Problems*)" % c.why_missing("coast", "gb", "mesh", 1), frange(vals(mesh_rs, "mesh_s"), 3),
                 "-", "-", "-", "-"])
    crows.append(["mesh", 1, len(mesh_rs), med(vals(mesh_rs, "triangles")), mw, None, None, None, None])
    for np_ in (2, 8):
        m = {}
        for prog in ("pcdm", "pbw"):
            rs = c.sel("coast", "gb", prog, np_)
            m[prog] = (med(vals(rs, "mesh_s")), med(vals(rs, CPU)), rs)
        rw, rc_ = div(m["pbw"][0], m["pcdm"][0]), div(m["pbw"][1], m["pcdm"][1])
        for prog in ("pcdm", "pbw"):
            w, cpu, rs = m[prog]
            if not rs:
                rows.append(["./" + prog, np_, "NA (%s; see *Problems*)" % c.why_missing("coast", "gb", prog, np_)] +
                            ["NA"] * 5)
                continue
            last = prog == "pbw"
            rows.append(["./" + prog, np_, fi(med(vals(rs, "triangles"))), frange(vals(rs, "mesh_s"), 3),
                         frange(vals(rs, CPU), 3), fi(med(vals(rs, "rsr"))), f(div(w, mw)),
                         ("%s (wall), %s (cpu_max)%s" % (f(rw), f(rc_), "" if rw is None else
                          (" ok" if rw <= COAST_GOAL else " ABOVE GOAL"))) if last else "-"])
            crows.append([prog, np_, len(rs), med(vals(rs, "triangles")), w, cpu, med(vals(rs, "rsr")),
                          div(w, mw), rw if last else None])
        c.out.append("Coast P=%d: pbw/pcdm wall %s (goal <= %.1f), cpu_max %s; pcdm %s s, pbw %s s, ./mesh %s s" % (
            np_, f(rw), COAST_GOAL, f(rc_), f(m["pcdm"][0], 3), f(m["pbw"][0], 3), f(mw, 3)))
        c.keys["coast_ratio_%d" % np_] = f(rw)
    c.H(md_table(["program", "ranks", "triangles", "mesh s", "cpu_max s", "RSRs", "wall / ./mesh",
                  "pbw / pcdm"], rows))
    c.H()
    c.csv("coast.csv", ["program", "ranks", "runs", "triangles", "mesh_s", "cpu_max_s", "rsr",
                        "wall_vs_mesh", "pbw_over_pcdm_wall"], crows)


# ---------------------------------------------------------------------------- output (issue 12)
def sec_output(c):
    """The end-to-end runs with -o (bench.sh section "output"), rows from output.tsv."""
    lines = [ln.split("\t") for ln in read_lines(os.path.join(c.R, "output.tsv"))[1:] if ln.strip()]
    if not lines:
        return
    c.H("## Output without a gather (issue 12): end to end, and memory per rank")
    c.H()
    c.H("`./mesh -q 30 -a A -o P` and `mpirun -np 2 ./pcdm -q 30 -a A -o P` run back to back (launch to "
        "exit, files written).  mesh s = the program's `mesh_s` (meshing only); output s = pcdm's "
        "`output_s` (the output stage: interface check, numbering, writing; slowest rank).  Per "
        "rank: triangles of its part, peak RSS at the end and that peak per triangle of its own "
        "part (goal: <= 60).")
    c.H()
    rows, ocsv, pair = [], [], {}
    for ln in lines:
        ln += [""] * (9 - len(ln))
        label, prog, np_, area, rep, rc, ext, stats, ranks = ln[:9]
        st = parse_stats(stats)
        per = []
        for item in [x for x in ranks.split(",") if x]:
            r, tris, mb, bpt, _ = (item.split(":") + [""] * 5)[:5]
            per.append("r%s: %s tri, %s MB, %s B/tri" % (r, fi(num(tris)), mb, bpt))
        if rc == "0":
            pair.setdefault((label, rep), {})[prog] = num(ext)
        rows.append([label, prog, np_, area, rep, rc, ext, fi(st.get("triangles")), f(st.get("mesh_s")),
                     f(st.get("output_s")) if prog == "pcdm" else "-", "; ".join(per) or "-"])
        ocsv.append([label, prog, np_, area, rep, rc, ext, st.get("triangles"), st.get("mesh_s"),
                     st.get("output_s"), ranks])
    c.H(md_table(["size", "program", "ranks", "-a", "rep", "status", "launch to exit s", "triangles",
                  "mesh s", "output s", "per rank"], rows))
    c.H()
    ratios = []
    for (label, rep), d in sorted(pair.items()):
        if "mesh" in d and "pcdm" in d and d["mesh"]:
            ratios.append(d["pcdm"] / d["mesh"])
            c.H("- %s rep %s: pcdm / mesh end to end = %.2f (goal <= 0.6)" % (label, rep, ratios[-1]))
    if ratios:
        c.out.append("Output 10M: pcdm(2)/mesh end to end %s" % ", ".join("%.2f" % x for x in ratios))
    c.H()
    c.csv("output.csv", ["size", "program", "ranks", "area", "rep", "rc", "launch_to_exit_s", "triangles",
                         "mesh_s", "output_s", "ranks_triangles_peakmb_bpt_outputs"], ocsv)


# ---------------------------------------------------------------------------- threads (issue 27)
def sec_threads(c):
    """./pcdm --threads 2 as one process against ./mesh and against two ranks (bench.sh section
    "threads"): rows from threads.tsv, the summary line bench.sh computed in threads.txt."""
    lines = [ln.split("\t") for ln in read_lines(os.path.join(c.R, "threads.tsv"))[1:] if ln.strip()]
    if not lines:
        return
    c.H("## Threads: one process on every core")
    c.H()
    c.H("`./mesh -q 30 -a A -o P`, `./pcdm --threads 2 -q 30 -a A -o P` (a plain program, no mpirun), "
        "`mpirun --bind-to none -np 1 ./pcdm --threads 2 ...` and `mpirun -np 2 ./pcdm ...`, in alternation (launch "
        "to exit, files written).  mesh s = the program's `mesh_s`; peak MB = each rank's peak RSS, "
        "summed over the ranks.")
    c.H()
    rows = []
    for ln in lines:
        ln += [""] * (9 - len(ln))
        label, prog, np_, area, rep, rc, ext, stats, ranks = ln[:9]
        st = parse_stats(stats)
        mb = sum(num(x.split(":")[2]) or 0 for x in ranks.split(",") if x.count(":") >= 2)
        how = {"thr": "./mesh" if prog == "mesh" else "./pcdm --threads 2",
               "mpi_t2": "mpirun --bind-to none -np 1 ./pcdm --threads 2", "mpi_np2": "mpirun -np 2 ./pcdm"}.get(label, label)
        rows.append([how, rep, rc, ext, fi(st.get("triangles")), f(st.get("mesh_s")),
                     fi(st.get("subdomains")) if st.get("subdomains") is not None else "-", "%.0f" % mb if mb else "-"])
    c.H(md_table(["run", "rep", "status", "launch to exit s", "triangles", "mesh s", "subdomains",
                  "peak MB (sum)"], rows))
    c.H()
    for ln in read_lines(os.path.join(c.R, "threads.txt")):
        if ln.strip():
            c.H("- " + ln.strip().replace("bench: threads: ", ""))
            c.out.append(ln.strip().replace("bench: ", ""))
    c.H()


# ---------------------------------------------------------------------------- problems, timing, commands
SIG = {"134": "SIGABRT (abort)", "137": "SIGKILL (out of memory or killed)", "139": "SIGSEGV",
       "143": "SIGTERM from outside the bench", "136": "SIGFPE"}


def describe_rc(rc):
    if rc in SIG:
        return "exit status %s: killed by %s" % (rc, SIG[rc])
    if rc.startswith("timeout"):
        return "%s: no result within the per-run time limit (hang or far too slow)" % rc
    if rc.startswith("skipped-after-timeout"):
        return "skipped: this cell timed out before"
    if rc.startswith("cut-budget"):
        return "%s: stopped when the time budget ran out" % rc
    if rc.startswith("skipped-budget"):
        return "%s: not started, the time budget would not allow it" % rc
    if rc == "nostats":
        return "exit status 0 but no `stats:` line"
    return "exit status %s" % rc


def sec_tail(c):
    bad = [r for r in c.runs if not r["ok"]]
    c.H("## Problems")
    c.H()
    if not c.notes and not bad:
        c.H("None: every program existed and every run succeeded.")
    else:
        for n in c.notes:
            c.H("* " + n)
        miss = [r for r in bad if r["rc"] == "missing"]
        if miss:
            c.H("* %d run(s) skipped because the program is missing (%s)." %
                (len(miss), ", ".join(sorted(set(r["prog"] for r in miss)))))
        for r in bad:
            if r["rc"] == "missing":
                continue
            logs = (" (log: `%s.out`, `%s.err`)" % (r["log"], r["log"])) if r.get("log") else ""
            c.H("* %s %s/%s np=%d rep %s: **%s**%s" % (r["prog"], r["section"], r["label"], r["np"], r["rep"],
                                                       describe_rc(r["rc"]), logs))
    c.H()
    c.H("## Time taken")
    c.H()
    c.H(md_table(["section", "elapsed s"], [[s[0], s[1]] for s in c.sections if len(s) >= 2]))
    c.H()
    c.H("## Files")
    c.H()
    c.H("CSV per table: " + ", ".join("[%s](%s)" % (x, x) for x in c.csvs) +
        ".  Raw data: [runs.tsv](runs.tsv) (one line per run, with its full `stats:` line and, in "
        "`extra`, its `rsr:`/`cavities:`/`blocking:` lines), [meta.txt](meta.txt); logs in `logs/`.")
    c.H()
    c.H("## Exact commands")
    c.H()
    c.H("As run (areas as calibrated above).  In the 1M/10M scale runs each process was additionally "
        "wrapped in `/usr/bin/time -a -o FILE -f %M` (or a python getrusage shim) to record its peak "
        "RSS; that wrapper is not shown.")
    c.H()
    c.H("```")
    c.H("\n".join(c.commands))
    c.H("```")
    c.H()


# ---------------------------------------------------------------------------- stdout summary
def summary(c):
    """Prints the summary; the last line keeps the historical keys first, new keys after."""
    print()
    print("Tables 2/3 (imbalanced 2:1, -a %s): mesh s | cpu_max s (lower bound) | RSRs   [paper s | RSRs]"
          % c.areas["area_43k"])
    for prog in ("pbw", "pcdm"):
        for np_ in NPS:
            d = c.cell.get(("t23", "imb2", prog, np_)) or {}
            print("  %-4s P=%d  wall %6s  cpu_max %6s  rsr %6s  speedup(cpu bound) %5s   [paper %5.2f s  %4d RSRs]" % (
                prog, np_, f(d.get("wall_m")), f(d.get("cpu_m"), 3), fi(med(d.get("all", []))),
                f(d.get("cpu_sp")), PAPER[prog]["time"][np_], PAPER[prog]["rsr"][np_]))
    for name, _ in CONVENTIONS:
        parts = ["P=%d %s" % (p, f(c.conv.get(("imb2", p), {}).get(name, (0, 0, None))[2])) for p in NPS[1:]]
        print("RSR ratio PBW/PCDM imb2 %-9s %s%s" % (name + ":", "  ".join(parts),
                                                    "   <- closest to the paper" if name == getattr(c, "best", None) else ""))
    print("   [paper P=2 8.19  P=4 6.40  P=8 6.87]")
    for line in c.out:
        print(line)
    print("Report: %s" % os.path.join(c.R, "report.md"))

    def g(prog, key, section="t23", label="imb2"):
        d = c.cell.get((section, label, prog, 8)) or {}
        x = d.get(key)
        return med(x) if isinstance(x, list) else x

    pc_r, pb_r = g("pcdm", "all"), g("pbw", "all")
    ratio = div(pb_r, pc_r)
    ratio_s = f(ratio) if ratio is not None else ("inf" if isnum(pb_r) and pb_r > 0 and pc_r == 0 else "NA")
    conv8 = c.conv.get(("imb2", 8), {})
    new = [("cores", str(c.cores)), ("headline_8", "wall" if c.headline(8) else "cpu_bound"),
           ("pcdm_wall_speedup_8", f(g("pcdm", "wall_sp"))), ("pbw_wall_speedup_8", f(g("pbw", "wall_sp"))),
           ("ratio_requests_8", f(conv8.get("requests", (0, 0, None))[2])),
           ("ratio_unique_8", f(conv8.get("unique", (0, 0, None))[2])),
           ("ratio_mpi_8", f(conv8.get("mpi", (0, 0, None))[2])),
           ("best_convention", getattr(c, "best", None) or "NA"),
           ("pcdm_wall_1m_8", f(g("pcdm", "wall_m", "t23m", "1m"), 3)),
           ("pbw_wall_1m_8", f(g("pbw", "wall_m", "t23m", "1m"), 3)),
           ("pcdm_cpu_speedup_1m_8", f(g("pcdm", "cpu_sp", "t23m", "1m"))),
           ("pbw_cpu_speedup_1m_8", f(g("pbw", "cpu_sp", "t23m", "1m")))]
    for k in ("comm_ratio_1m_8", "pbw_sp2_slowdown_8", "pcdm_sp2_slowdown_8", "null_rsr_ratio",
              "dyn_wall_vs_balanced_2", "dyn_cpu_speedup_vs_balanced_8", "det_cost_wall",
              "coast_ratio_2", "coast_ratio_8"):
        new.append((k, c.keys.get(k, "NA")))
    print("bench: pcdm_rsr_8=%s pbw_rsr_8=%s ratio_8=%s pcdm_wall_8=%s pbw_wall_8=%s "
          "pcdm_speedup_model_8=%s pbw_speedup_model_8=%s %s" % (
              fi(pc_r), fi(pb_r), ratio_s, f(g("pcdm", "wall_m"), 3), f(g("pbw", "wall_m"), 3),
              f(g("pcdm", "cpu_sp")), f(g("pbw", "cpu_sp")), " ".join("%s=%s" % kv for kv in new)))


def main():
    R = sys.argv[1] if len(sys.argv) > 1 else "bench/results"
    c = Ctx(R)
    c.best, c.score = None, {}
    sec_header(c)
    sec_definitions(c)
    sec_calibration(c)
    sec_table23(c, "pbw", 2)
    sec_table23(c, "pcdm", 3)
    sec_tables_big(c)
    sec_rsr_kinds(c)
    sec_conventions(c)
    sec_comm(c)
    sec_net(c)
    sec_analysis(c)
    sec_plots(c)
    sec_overhead(c)
    sec_balance(c)
    sec_primitives(c)
    sec_figures(c)
    sec_decomp(c)
    sec_scale(c)
    sec_coast(c)
    sec_coast_scale(c)
    sec_output(c)
    sec_threads(c)
    sec_tail(c)
    with open(os.path.join(R, "report.md"), "w") as fh:
        fh.write("\n".join(c.report))
    summary(c)


if __name__ == "__main__":
    main()
