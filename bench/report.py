#!/usr/bin/env python3
"""Turn the raw runs of bench/bench.sh into bench/results/report.md, CSVs and SVG plots.

Usage: python3 bench/report.py [RESULTS_DIR]   (default bench/results)

Reads RESULTS_DIR/{meta.txt,runs.tsv,sections.tsv,notes.txt,calibration.tsv,commands.txt,
primitives.txt}.  Every number written comes from those files, except the published figures of
TR-97-17, which are in PAPER below and always labelled as the paper's.  Prints a summary; the
last line is
  bench: pcdm_rsr_8=N pbw_rsr_8=M ratio_8=R pcdm_wall_8=S pbw_wall_8=T pcdm_speedup_model_8=X pbw_speedup_model_8=Y
Standard library only.
"""
import csv
import math
import os
import statistics
import sys

# The "modelled" time of a parallel run: the busiest rank's CPU seconds (see the report text).
MODEL = "cpu_max_s"

# ---------------------------------------------------------------------------- the paper's figures
# Chew, Chrisochoides, Sukup, TR-97-17 (1997), section 4; IBM SP2 "thin" nodes, 22K sites / 43K
# triangles, two-to-one imbalanced load.
PAPER = {
    "pbw": {"time": {1: 8.51, 2: 4.38, 4: 2.89, 8: 1.91}, "rsr": {1: 0, 2: 516, 4: 807, 8: 866}},
    "pcdm": {"time": {1: 8.51, 2: 3.59, 4: 2.29, 8: 1.48}, "rsr": {1: 0, 2: 63, 4: 126, 8: 126}},
}
PAPER_OVH = {"comm_pct": 27.0, "undo_pct": 1.0, "ranks": 4, "sites": 65500, "triangles": 129400}
PAPER_PRIM = [  # (our key, our label, paper value, paper label)
    ("null_rsr_us", "null non-threaded RSR, round trip (us)", 31.0, "null non-threaded RSR: 31 us"),
    ("raw_mpi_roundtrip_us", "raw MPI 0-byte round trip (us)", 58.0,
     "one-way latency, 0-byte message: 29 us (x2 = 58 us round trip)"),
    ("ratio", "null RSR / raw MPI round trip", None, "-"),
    ("threaded_rsr_us", "null threaded RSR, round trip (us)", None,
     "- (paper: thread creation 12 us, context switch 5.5 us; see the full table below)"),
    ("bandwidth_MBps", "peak bandwidth (MB/s)", 33.6, "peak data-transfer bandwidth: 33.6 MB/s"),
]
NPS = [1, 2, 4, 8]
PROG_NAME = {"pbw": "PBW (Parallel Meshing Algorithm, ./pbw)",
             "pcdm": "PCDM (Parallel Constrained Meshing Algorithm, ./pcdm)"}
CONF_NAME = {"imb2": "two-to-one imbalanced (--imbalance 2, the paper's setting)",
             "imb1": "balanced (no --imbalance)"}


# ---------------------------------------------------------------------------- small helpers
def num(s):
    try:
        v = float(s)
    except (TypeError, ValueError):
        return s
    return v


def parse_stats(s):
    d = {}
    for tok in (s or "").split():
        if "=" in tok:
            k, v = tok.split("=", 1)
            d[k] = num(v)
    return d


def isnum(v):
    return isinstance(v, (int, float)) and not (isinstance(v, float) and math.isnan(v))


def med(xs):
    xs = [x for x in xs if isnum(x)]
    return statistics.median(xs) if xs else None


def lo(xs):
    xs = [x for x in xs if isnum(x)]
    return min(xs) if xs else None


def hi(xs):
    xs = [x for x in xs if isnum(x)]
    return max(xs) if xs else None


def f(v, nd=2):
    """Format a number, or NA."""
    if v is None or not isnum(v):
        return "NA"
    if abs(v - round(v)) < 1e-9 and abs(v) >= 1 and nd <= 2 and abs(v) < 1e15:
        return "%d" % round(v) if nd == 0 else ("%.*f" % (nd, v))
    return "%.*f" % (nd, v)


def fi(v):
    return "NA" if v is None or not isnum(v) else "%d" % round(v)


def frange(xs, nd=2, integer=False):
    """'median (min-max)' or just the value when there is one sample."""
    vals = [x for x in xs if isnum(x)]
    if not vals:
        return "NA"
    fm = fi if integer else (lambda v: f(v, nd))
    if len(vals) == 1:
        return fm(vals[0])
    return "%s (%s-%s)" % (fm(med(vals)), fm(min(vals)), fm(max(vals)))


def div(a, b):
    if a is None or b is None or not isnum(a) or not isnum(b) or b == 0:
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


def write_csv(path, header, rows):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for r in rows:
            w.writerow(["" if c is None else c for c in r])


# ---------------------------------------------------------------------------- load
R = sys.argv[1] if len(sys.argv) > 1 else "bench/results"
meta = read_kv(os.path.join(R, "meta.txt"))
notes = [n for n in read_lines(os.path.join(R, "notes.txt")) if n.strip()]
sections = [ln.split("\t") for ln in read_lines(os.path.join(R, "sections.tsv")) if ln.strip()]
calib = [ln.split("\t") for ln in read_lines(os.path.join(R, "calibration.tsv")) if ln.strip()]
commands = read_lines(os.path.join(R, "commands.txt"))
runs = []
runs_path = os.path.join(R, "runs.tsv")
if os.path.exists(runs_path):
    with open(runs_path) as fh:
        rd = csv.DictReader(fh, delimiter="\t", quoting=csv.QUOTE_NONE)
        for row in rd:
            row["np"] = int(row["np"])
            row["s"] = parse_stats(row.get("stats"))
            row["ok"] = row["rc"] == "0"
            row["ext_s"] = num(row.get("ext_s"))
            row["rss_sum_kb"] = num(row.get("rss_sum_kb"))
            row["rss_max_kb"] = num(row.get("rss_max_kb"))
            runs.append(row)
missing = set()
for m in meta.get("missing_list", []):
    missing.add(os.path.basename(m))


def sel(section, label=None, prog=None, np_=None, ok=True):
    out = []
    for r in runs:
        if r["section"] != section:
            continue
        if label is not None and r["label"] != label:
            continue
        if prog is not None and r["prog"] != prog:
            continue
        if np_ is not None and r["np"] != np_:
            continue
        if ok and not r["ok"]:
            continue
        out.append(r)
    return out


def vals(rs, key):
    return [r["s"].get(key) for r in rs]


def why_missing(section, label, prog, np_):
    rs = sel(section, label, prog, np_, ok=False)
    if not rs:
        return "not run"
    sts = sorted(set(r["rc"] for r in rs))
    return "/".join(sts)


report = []
csvs = []
stdout = []


def H(s):
    report.append(s)


# ---------------------------------------------------------------------------- header
H("# PCDM vs PBW: reproduction of TR-97-17 section 4, and beyond")
H("")
H("Generated by `%s` on this machine; every number below comes from this run except the "
  "columns and rows marked **paper**, which are the published figures of Chew, Chrisochoides "
  "and Sukup, *Parallel Constrained Delaunay Meshing*, Cornell TR-97-17 (1997), measured on an "
  "8-node IBM SP2 with \"thin\" nodes." % meta.get("invocation", "bash bench/bench.sh"))
H("")
H(md_table(["", ""], [
    ["date", meta.get("date", "NA")],
    ["git commit", "`%s`" % meta.get("commit", "NA")],
    ["mode", "%s (%s repetition(s) per cell)" % (meta.get("mode", "NA"), meta.get("reps", "NA"))],
    ["machine", "%s, %s cores (nproc), %s, %s memory" % (meta.get("host", "?"), meta.get("nproc", "?"),
                                                      meta.get("cpu", "?"), meta.get("mem", "?"))],
    ["kernel", meta.get("kernel", "NA")],
    ["MPI", meta.get("mpirun", "NA")],
    ["compiler", meta.get("cc", "NA")],
    ["domain", "`%s`, `-q %s`" % (meta.get("domain", "?"), meta.get("qdeg", "?"))],
    ["Triangle", meta.get("triangle", "not available")],
]))
H("")
nproc = meta.get("nproc", "?")
H("**Time on this machine.** It has %s cores; runs on more ranks than cores share them "
  "(`mpirun --oversubscribe`), so their *wall* time cannot show parallel speedup beyond %s. "
  "Every table therefore reports two different things, never mixed:" % (nproc, nproc))
H("")
H("* **wall s**: the program's own elapsed time (`wall_s` of its `stats:` line, rank 0), "
  "as measured here on %s shared cores;" % nproc)
H("* **modelled s**: `cpu_max_s`, the CPU seconds of the busiest rank (user + system, from "
  "`getrusage`, over the same span as `wall_s`).  Unlike wall-clock busy time it does not grow "
  "while a rank waits for one of the %s shared cores, so it estimates the time the run would take "
  "if every rank had a core of its own.  **Modelled speedup** = T1 / cpu_max_P with T1 = the same "
  "program's median `cpu_max_s` on 1 rank.  **busy_sum/busy_max** (wall-clock busy time of the "
  "runtime's work and handler buckets, summed and maximised over ranks) is the load-balance bound "
  "the issue asks for: the speedup if the total work were spread as it is, with no idle time.  "
  "These are models, not measurements of a P-core machine." % nproc)
H("")
try:
    l0 = float(meta.get("loadavg_start", "0").split()[0])
except (ValueError, IndexError):
    l0 = 0.0
try:
    ncores = int(nproc)
except ValueError:
    ncores = 1
H("**Machine load**: load average %s at the start, %s at the end.%s" % (
    meta.get("loadavg_start", "NA"), meta.get("loadavg_end", "NA"),
    (" **The machine was busy with other work when this run started (load %.1f on %d cores): "
     "the times below are inflated and noisy, and the RSR counts, which depend on message "
     "timing, may differ from an idle machine's.**" % (l0, ncores)) if l0 > 0.5 * ncores else ""))
H("")
if notes or missing:
    H("**Problems in this run** (details in the section *Problems* at the end):")
    H("")
    for n in notes:
        H("* " + n)
    H("")

# ---------------------------------------------------------------------------- calibration
areas = {k: meta.get(k) for k in ("area_43k", "area_129k", "area_1m", "area_10m", "area_fig")}
H("## Calibration of the area bound")
H("")
H("Triangles scale about as 1/area, so a few `./mesh` runs find the `-a` that gives the paper's "
  "size (43K triangles, 22K sites) and the overhead run's size (129.4K triangles, 65.5K sites). "
  "The 1M and 10M bounds are extrapolated from the 129.4K calibration; the triangle counts in "
  "the tables are the ones the runs actually produced.")
H("")
crow = [[c[0], c[1], c[2]] for c in calib]
H(md_table(["target triangles", "-a tried", "./mesh triangles"], crow) if crow else
  "_No calibration runs (./mesh missing); fixed areas used._")
H("")
H("Chosen: 43K: `-a %s`, 129.4K: `-a %s`, 1M: `-a %s`, 10M: `-a %s`, figures: `-a %s`." %
  tuple(areas[k] or "NA" for k in ("area_43k", "area_129k", "area_1m", "area_10m", "area_fig")))
H("")
write_csv(os.path.join(R, "calibration.csv"), ["target_triangles", "area", "mesh_triangles"], crow)
csvs.append("calibration.csv")

# ---------------------------------------------------------------------------- Tables 2 and 3
seq = sel("t23", "seq", "mesh", 1)
seq_wall = med(vals(seq, "wall_s"))
seq_tris = med(vals(seq, "triangles"))

cell = {}  # (prog, conf, np) -> dict of medians


def table23(prog, tabno):
    H("## Table %d: %s" % (tabno, PROG_NAME[prog]))
    H("")
    H("Domain `%s`, `-q %s -a %s` (calibrated for ~43K triangles); paper: 22K sites, 43K "
      "triangles, SP2.  Times in seconds, median of the repetitions with (min-max). "
      "RSRs: %s." % (meta.get("domain"), meta.get("qdeg"), areas["area_43k"],
                     "all remote service requests (`rsr`)" if prog == "pbw"
                     else "split-constraint-edge RSRs (`rsr`)"))
    H("")
    if seq_wall is not None:
        H("Sequential `./mesh` at the same bound: %s triangles in %s s wall (for scale; the "
          "paper's 1-node time, 8.51 s, is its parallel code on one node)." % (fi(seq_tris), f(seq_wall, 3)))
        H("")
    header = ["config", "ranks", "triangles", "vertices", "wall s", "**paper** s", "modelled s (cpu_max)",
              "busy_sum s", "RSRs", "**paper** RSRs", "wall speedup", "modelled speedup",
              "busy_sum/busy_max", "**paper** speedup", "min angle"]
    csvh = ["config", "ranks", "runs", "triangles", "vertices", "wall_s_median", "wall_s_min", "wall_s_max",
            "paper_time_s", "cpu_max_s_median", "cpu_max_s_min", "cpu_max_s_max", "busy_sum_s_median",
            "rsr_median", "rsr_min", "rsr_max", "paper_rsr", "wall_speedup", "modelled_speedup",
            "busy_sum_over_busy_max", "paper_speedup", "min_angle_min", "launch_plus_run_s_median"]
    rows, crows = [], []
    for conf in ("imb2", "imb1"):
        base = sel("t23", conf, prog, 1)
        t1_wall = med(vals(base, "wall_s"))
        t1_busy = med(vals(base, MODEL))
        for np_ in NPS:
            rs = sel("t23", conf, prog, np_)
            pt = PAPER[prog]["time"][np_] if conf == "imb2" else None
            pr = PAPER[prog]["rsr"][np_] if conf == "imb2" else None
            psp = PAPER[prog]["time"][1] / pt if pt else None
            if not rs:
                w = why_missing("t23", conf, prog, np_)
                rows.append([conf, np_, "NA (%s)" % w, "NA", "NA", f(pt) if pt else "-", "NA", "NA", "NA",
                             fi(pr) if pr is not None else "-", "NA", "NA", "NA", f(psp) if psp else "-", "NA"])
                crows.append([conf, np_, 0] + [None] * 5 + [pt] + [None] * 7 + [pr] + [None] * 3 + [psp, None, None])
                continue
            w = vals(rs, "wall_s")
            bm = vals(rs, "busy_max_s")
            bs = vals(rs, "busy_sum_s")
            rsr = vals(rs, "rsr")
            c = {"wall": med(w), "busy_max": med(vals(rs, MODEL)), "busy_sum": med(bs), "rsr": med(rsr),
                 "tris": med(vals(rs, "triangles")), "verts": med(vals(rs, "vertices"))}
            c["wall_speedup"] = div(t1_wall, c["wall"])
            c["model_speedup"] = div(t1_busy, c["busy_max"])
            c["lb"] = div(c["busy_sum"], med(bm))
            cell[(prog, conf, np_)] = c
            mina = lo(vals(rs, "min_angle"))
            rows.append([conf, np_, fi(c["tris"]), fi(c["verts"]), frange(w), f(pt) if pt else "-",
                         frange(vals(rs, MODEL), 3), f(c["busy_sum"], 3), frange(rsr, integer=True),
                         fi(pr) if pr is not None else "-", f(c["wall_speedup"]), f(c["model_speedup"]),
                         f(c["lb"]), f(psp) if psp else "-", f(mina, 2)])
            crows.append([conf, np_, len(rs), c["tris"], c["verts"], c["wall"], lo(w), hi(w), pt, c["busy_max"],
                          lo(vals(rs, MODEL)), hi(vals(rs, MODEL)), c["busy_sum"], c["rsr"], lo(rsr), hi(rsr), pr,
                          c["wall_speedup"], c["model_speedup"], c["lb"], psp, mina,
                          med([r["ext_s"] for r in rs])])
    H(md_table(header, rows))
    H("")
    H("`imb2` = %s; `imb1` = %s.  The paper gives only the imbalanced case.  Wall speedup = "
      "median wall on 1 rank / median wall on P ranks (on %s shared cores); paper speedup = "
      "8.51 s / paper time." % (CONF_NAME["imb2"], CONF_NAME["imb1"], nproc))
    H("")
    name = "table%d_%s.csv" % (tabno, prog)
    write_csv(os.path.join(R, name), csvh, crows)
    csvs.append(name)


table23("pbw", 2)
table23("pcdm", 3)

# ratio table
H("## RSRs: PBW / PCDM")
H("")
H("The paper's headline: using the CDT cuts communication by a factor of about seven. "
  "Ratio of the median RSR counts (Tables 2 and 3) per rank count.")
H("")
rrows, rcsv = [], []
for conf in ("imb2", "imb1"):
    for np_ in NPS[1:]:
        pb = cell.get(("pbw", conf, np_), {}).get("rsr")
        pc = cell.get(("pcdm", conf, np_), {}).get("rsr")
        ratio = div(pb, pc)
        pp = div(PAPER["pbw"]["rsr"][np_], PAPER["pcdm"]["rsr"][np_]) if conf == "imb2" else None
        rrows.append([conf, np_, fi(pb), fi(pc), f(ratio) if ratio is not None else
                      ("inf" if isnum(pb) and pb > 0 and pc == 0 else "NA"),
                      f(pp) if pp else "-"])
        rcsv.append([conf, np_, pb, pc, ratio, PAPER["pbw"]["rsr"][np_] if conf == "imb2" else None,
                     PAPER["pcdm"]["rsr"][np_] if conf == "imb2" else None, pp])
H(md_table(["config", "ranks", "PBW RSRs", "PCDM RSRs", "PBW/PCDM", "**paper** PBW/PCDM"], rrows))
H("")
write_csv(os.path.join(R, "rsr_ratio.csv"), ["config", "ranks", "pbw_rsr", "pcdm_rsr", "ratio",
                                             "paper_pbw_rsr", "paper_pcdm_rsr", "paper_ratio"], rcsv)
csvs.append("rsr_ratio.csv")


# ---------------------------------------------------------------------------- plot
def svg_plot(conf, path):
    """Three panels against ranks: RSRs (log y), time (log y), speedup (linear, with ideal)."""
    pw, ph, gap, left, top = 250, 230, 80, 70, 50
    W, Hh = left + 3 * pw + 2 * gap + 20, top + ph + 170
    colors = {"pbw": "#d62728", "pcdm": "#1f77b4"}
    p_sp = {p: {n: PAPER[p]["time"][1] / PAPER[p]["time"][n] for n in NPS} for p in PAPER}
    panels = []
    s_rsr, s_time, s_sp = [], [], []
    for prog in ("pbw", "pcdm"):
        g = lambda key: {n: cell.get((prog, conf, n), {}).get(key) for n in NPS}
        s_rsr.append(("%s RSRs, this run" % prog, colors[prog], "", g("rsr")))
        s_time.append(("%s modelled (cpu_max), this run" % prog, colors[prog], "", g("busy_max")))
        s_time.append(("%s wall on %s cores, this run" % (prog, nproc), colors[prog], "2,3", g("wall")))
        s_sp.append(("%s modelled speedup, this run" % prog, colors[prog], "", g("model_speedup")))
        s_sp.append(("%s wall speedup, this run" % prog, colors[prog], "2,3", g("wall_speedup")))
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
         'this run vs the paper</text>' % (W // 2, meta.get("domain", ""), meta.get("qdeg", ""),
                                           areas["area_43k"], {"imb2": "2:1 imbalanced",
                                                               "imb1": "balanced"}[conf])]
    for pi, (ylabel, logy, series) in enumerate(panels):
        x0, y0 = left + pi * (pw + gap), top
        ys = [v for _, _, _, sr in series for v in sr.values() if isnum(v) and (v > 0 or not logy)]
        if logy:
            if not ys:
                ys = [1.0, 10.0]
            lmin = math.floor(math.log10(min(ys)))
            lmax = math.ceil(math.log10(max(ys)))
            if lmax == lmin:
                lmax += 1
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
            yy = Y(t)
            o.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (x0, yy, x0 + pw, yy))
            o.append('<text x="%d" y="%.1f" text-anchor="end">%s</text>' % (x0 - 4, yy + 4, "%g" % round(t, 4)))
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


H("## Plot: RSRs and time against ranks")
H("")
for conf in ("imb2", "imb1"):
    name = "plot_%s.svg" % conf
    svg_plot(conf, os.path.join(R, name))
    H("%s: [%s](%s)" % (CONF_NAME[conf], name, name))
    H("")
    H("![RSRs and time vs ranks, %s](%s)" % (conf, name))
    H("")
H("Solid: this run's RSRs, modelled time (cpu_max_s) and modelled speedup.  Dotted: this run's "
  "wall time and wall speedup on this machine's %s cores.  Dashed: the paper's published "
  "figures (SP2; imbalanced plot only)." % nproc)
H("")

# ---------------------------------------------------------------------------- overhead
H("## PBW overhead breakdown (paper: 4 processors, 65.5K sites, 129.4K triangles)")
H("")
H("Paper: communication overhead about 27%%, undo-computation overhead about 1%%.  Ours: "
  "`comm_pct` and `undo_pct` from `./pbw --stats` on 4 ranks at `-a %s` (calibrated for "
  "~129.4K triangles), median (min-max); `./pcdm` on the same input beside it." % areas["area_129k"])
H("")
orows, ocsv = [], []
for conf in ("imb2", "imb1"):
    for prog in ("pbw", "pcdm"):
        rs = sel("ovh", conf, prog, 4)
        if not rs:
            orows.append([conf, prog, "NA (%s)" % why_missing("ovh", conf, prog, 4)] + ["NA"] * 7 +
                         (["27", "1"] if prog == "pbw" else ["-", "-"]))
            continue
        cp, up = vals(rs, "comm_pct"), vals(rs, "undo_pct")
        orows.append([conf, prog, fi(med(vals(rs, "triangles"))), fi(med(vals(rs, "vertices"))),
                      frange(vals(rs, "wall_s")), frange(vals(rs, "busy_max_s"), 3),
                      frange(vals(rs, "rsr"), integer=True),
                      frange(vals(rs, "undone"), integer=True) if prog == "pbw" else "-",
                      frange(cp, 1), frange(up, 1) if prog == "pbw" else "-",
                      "27" if prog == "pbw" else "-", "1" if prog == "pbw" else "-"])
        ocsv.append([conf, prog, 4, len(rs), med(vals(rs, "triangles")), med(vals(rs, "vertices")),
                     med(vals(rs, "wall_s")), med(vals(rs, "busy_max_s")), med(vals(rs, "rsr")),
                     med(vals(rs, "undone")), med(cp), lo(cp), hi(cp), med(up), lo(up), hi(up),
                     PAPER_OVH["comm_pct"] if prog == "pbw" else None,
                     PAPER_OVH["undo_pct"] if prog == "pbw" else None])
H(md_table(["config", "program", "triangles", "vertices", "wall s", "modelled s", "RSRs", "undone",
            "comm %", "undo %", "**paper** comm %", "**paper** undo %"], orows))
H("")
H("`comm %` and `undo %` are the programs' own accounting (see their `--help`/source for the "
  "exact definition); NA means the key is absent from the `stats:` line.")
H("")
write_csv(os.path.join(R, "overhead.csv"),
          ["config", "program", "ranks", "runs", "triangles", "vertices", "wall_s", "busy_max_s", "rsr",
           "undone", "comm_pct_median", "comm_pct_min", "comm_pct_max", "undo_pct_median", "undo_pct_min",
           "undo_pct_max", "paper_comm_pct", "paper_undo_pct"], ocsv)
csvs.append("overhead.csv")

# ---------------------------------------------------------------------------- primitives
H("## Primitive costs (`bash bench/primitives.sh`, 2 ranks)")
H("")
ptxt = read_lines(os.path.join(R, "primitives.txt"))
prc = (read_lines(os.path.join(R, "primitives.rc")) or ["rc=?"])[0]
pline = [ln for ln in ptxt if ln.startswith("primitives:")]
pst = parse_stats(pline[-1][len("primitives:"):]) if pline else {}
prow, pcsv = [], []
for k, lab, pv, plab in PAPER_PRIM:
    prow.append([lab, f(pst.get(k), 2) if k in pst else "NA", plab])
    pcsv.append([k, pst.get(k), pv, plab])
H(md_table(["primitive (this machine)", "this run", "**paper** (SP2, DMCS)"], prow))
H("")
if pline:
    H("Output of `bash bench/primitives.sh`:")
    H("")
    H("```")
    H("\n".join(ptxt))
    H("```")
else:
    perr = read_lines(os.path.join(R, "primitives.err"))
    H("**bench/primitives.sh produced no `primitives:` line (%s).**%s" %
      (prc, (" Last lines of its stderr:\n\n```\n%s\n```" % "\n".join(perr[-10:])) if perr else
       " It printed nothing (a timeout kills it; see notes)."))
    if ptxt:
        H("")
        H("```")
        H("\n".join(ptxt[-20:]))
        H("```")
H("")
write_csv(os.path.join(R, "primitives.csv"), ["key", "this_run", "paper_value", "paper_label"], pcsv)
csvs.append("primitives.csv")

# ---------------------------------------------------------------------------- figures
H("## Figures 1 and 3: meshes coloured by rank")
H("")
H("2 ranks, balanced, `-a %s` (a few thousand triangles).  The paper's Figure 1 is a PBW mesh "
  "(one mesh, triangles owned by ranks); Figure 3 a PCDM mesh (subdomains separated by "
  "constraint edges)." % areas["area_fig"])
H("")
for prog, fig in (("pbw", "Figure 1 (PBW)"), ("pcdm", "Figure 3 (PCDM)")):
    name = "fig_%s_2ranks.svg" % prog
    rs = sel("fig", "small", prog, 2)
    if rs and os.path.exists(os.path.join(R, name)):
        s = rs[0]["s"]
        H("%s: [%s](%s), %s triangles, %s RSRs" % (fig, name, name, fi(s.get("triangles")), fi(s.get("rsr"))))
        H("")
        H("![%s](%s)" % (fig, name))
    else:
        H("%s: not produced (%s)." % (fig, why_missing("fig", "small", prog, 2) if not rs else "no SVG written"))
    H("")

# ---------------------------------------------------------------------------- decomposition
H("## The decomposition (issue 11): balance, triangle count, cost")
H("")
H("`./pcdm` at 8 ranks with its default subdomains, `-q %s`, beside `./mesh` at the same bounds; "
  "one run each.  balance = the busiest rank's triangles / the mean over the ranks (measured "
  "counts; targets: <= 1.05 with an area bound, <= 1.10 with the angle bound alone); "
  "vs ./mesh = pcdm's triangles / ./mesh's - 1; decomp s = wall seconds rank 0 spent "
  "building the decomposition (every rank builds the same one); mesh s = pcdm's `wall_s` "
  "(meshing, after the decomposition)." % meta.get("qdeg", "20.7"))
H("")
drows = []
labels = sorted(set(r["label"] for r in runs if r["section"] == "decomp"))
for lab in labels:
    pc = sel("decomp", lab, "pcdm")
    ms = sel("decomp", lab, "mesh", 1)
    if not pc:
        drows.append([lab, "-", "-", "-", "-", "-", "-", "-", "-",
                      why_missing("decomp", lab, "pcdm", None)])
        continue
    s = pc[0]["s"]
    mt = ms[0]["s"].get("triangles") if ms else None
    bal = div(s.get("tri_max"), s.get("tri_mean"))
    rel = (div(s.get("triangles"), mt) - 1) * 100 if isnum(mt) and isnum(s.get("triangles")) else None
    share = div(s.get("decomp_s"), s.get("wall_s"))
    ex = s.get("decomp_exact")
    route = "exact" if ex == 1 else "coarse" if ex == 0 else "-"
    drows.append([lab, "%d" % pc[0]["np"], fi(s.get("subdomains")), route, fi(s.get("triangles")),
                  fi(mt), f(bal, 3), ("%+.2f%%" % rel) if rel is not None else "-",
                  f(s.get("decomp_s"), 3), ("%.1f%%" % (100 * share)) if isnum(share) else "-"])
H(md_table(["domain / bound", "ranks", "subdomains", "route", "pcdm triangles",
            "./mesh triangles", "balance", "vs ./mesh", "decomp s", "decomp / mesh s"], drows))
H("")
H("route: `exact` = the decomposition was drawn on the exact preview (the final mesh is small: "
  "the coarse mesh is the mesh at the real bounds, so the count matches ./mesh and the balance "
  "is of the actual triangles); `coarse` = the coarse quality mesh weighted by predicted work.  "
  "Where ./mesh makes fewer than 12 triangles per rank (square, lshape, wedge with the angle "
  "bound alone; 128 subdomains on 390 triangles) the count cannot match: every rank (every "
  "subdomain) needs triangles of its own.")
H("")
for row in drows:
    stdout.append("Decomp %-18s P=%s K=%s %-6s balance %s  vs ./mesh %s  decomp/mesh %s" %
                  (row[0], row[1], row[2], row[3], row[6], row[7], row[9]))

# ---------------------------------------------------------------------------- scale
H("## Beyond the paper: 1M and 10M triangles")
H("")
H("Balanced runs, one repetition.  Against the sequential `./mesh` and Shewchuk's Triangle (PyPI "
  "`triangle`, time of the `triangulate` call only, with switches `pq%sa<area>Q`). "
  "tri/s wall = triangles / wall s; tri/s modelled = triangles / cpu_max s; "
  "modelled speedup = the program's 1-rank cpu_max / cpu_max_P; vs ./mesh = ./mesh wall / "
  "cpu_max_P (for ./mesh and Triangle: ./mesh wall / their wall).  Memory = sum over the "
  "processes (ranks) of each one's peak RSS (`/usr/bin/time -f %%M` per process; Triangle: the "
  "python process's own peak, including the interpreter and numpy), divided by the triangle count; `own B/tri` is the program's own `bytes_per_tri` "
  "key when it prints one." % meta.get("qdeg", "20.7"))
H("")
srows, scsv = [], []
sizes = [lab for lab in ("1m", "10m") if sel("scale", lab, ok=False)]
for lab in sizes:
    mesh_rs = sel("scale", lab, "mesh", 1)
    mesh_wall = med(vals(mesh_rs, "wall_s"))
    order = [("mesh", 1), ("triangle", 1)] + [(p, n) for p in ("pcdm", "pbw") for n in NPS]
    t1 = {p: med(vals(sel("scale", lab, p, 1), MODEL)) for p in ("pcdm", "pbw")}
    for prog, np_ in order:
        all_rs = sel("scale", lab, prog, np_, ok=False)
        if not all_rs:
            continue
        rs = [r for r in all_rs if r["ok"]]
        if not rs:
            srows.append([lab, prog, np_, "NA (%s)" % why_missing("scale", lab, prog, np_)] + ["NA"] * 12)
            continue
        s = rs[0]["s"]
        tris = s.get("triangles")
        wall = s.get("wall_s")
        bm = s.get(MODEL) if prog in ("pcdm", "pbw") else wall
        rss_kb = rs[0]["rss_sum_kb"] if isnum(rs[0]["rss_sum_kb"]) else None
        if prog == "triangle" and isnum(s.get("peak_rss_mb")):
            rss_kb = s["peak_rss_mb"] * 1024.0
        bpt = div(rss_kb * 1024.0 if rss_kb else None, tris)
        own_bpt = s.get("bytes_per_tri") if isnum(s.get("bytes_per_tri")) else None
        msp = div(t1.get(prog), bm) if prog in ("pcdm", "pbw") else None
        vs_mesh = div(mesh_wall, bm)
        rsr = s.get("rsr") if prog in ("pcdm", "pbw") else None
        rsr_k = div(rsr * 1000.0, tris) if isnum(rsr) else None
        lb = div(s.get("busy_sum_s"), s.get("busy_max_s"))
        srows.append([lab, prog, np_, fi(tris), f(wall, 2), f(bm, 2) if prog in ("pcdm", "pbw") else "-",
                      fi(div(tris, wall)), fi(div(tris, bm)) if prog in ("pcdm", "pbw") else "-",
                      f(msp) if msp is not None else "-", f(vs_mesh), f(lb) if lb else "-",
                      f(rss_kb / 1024.0, 0) if rss_kb else "NA", fi(bpt), fi(own_bpt) if own_bpt else "-",
                      fi(rsr) if rsr is not None else "-", f(rsr_k, 3) if rsr_k is not None else "-"])
        scsv.append([lab, prog, np_, tris, s.get("vertices"), wall, s.get("busy_max_s"), s.get("busy_sum_s"),
                     div(tris, wall), div(tris, bm), msp, vs_mesh, lb, rss_kb / 1024.0 if rss_kb else None,
                     bpt, own_bpt, rsr, rsr_k, s.get("min_angle"), rs[0]["area"]])
if srows:
    H(md_table(["size", "program", "ranks", "triangles", "wall s", "modelled s", "tri/s wall", "tri/s modelled",
                "modelled speedup", "vs ./mesh", "busy_sum/busy_max", "peak MB (sum)", "B/tri", "own B/tri",
                "RSRs", "RSRs/1000 tri"], srows))
else:
    H("_No scale runs._")
H("")
write_csv(os.path.join(R, "scale.csv"),
          ["size", "program", "ranks", "triangles", "vertices", "wall_s", "busy_max_s", "busy_sum_s",
           "tri_per_s_wall", "tri_per_s_modelled", "modelled_speedup", "speedup_vs_mesh_modelled",
           "busy_sum_over_busy_max", "peak_rss_mb_sum", "bytes_per_tri", "own_bytes_per_tri", "rsr",
           "rsr_per_1000_tri", "min_angle", "area"], scsv)
csvs.append("scale.csv")

# ---------------------------------------------------------------------------- output (issue 12)
def output_section():
    """The end-to-end runs with -o (bench.sh section "output"): ./mesh against ./pcdm on 2
    ranks, back to back, and the BENCH_100M run; rows from output.tsv."""
    path = os.path.join(R, "output.tsv")
    lines = [ln.split("\t") for ln in read_lines(path)[1:] if ln.strip()] if os.path.exists(path) else []
    if not lines:
        return
    H("## Output without a gather (issue 12): end to end, and memory per rank")
    H("")
    H("`./mesh -q 30 -a A -o P` and `mpirun -np 2 ./pcdm -q 30 -a A -o P` run back to back "
      "(launch to exit, files written; the machine may be shared: see the load average above). "
      "mesh s = the program's `wall_s` (meshing only); output s = pcdm's `output_s` (numbering + "
      "writing, slowest rank).  Per rank: triangles of its part, peak RSS at the end (after the "
      "output) and that peak per triangle of its own part (goal: <= 60).")
    H("")
    rows, ocsv = [], []
    pair = {}
    for ln in lines:
        ln += [""] * (9 - len(ln))
        label, prog, np_, area, rep, rc, ext, stats, ranks = ln[:9]
        st = parse_stats(stats)
        per = []
        for item in [x for x in ranks.split(",") if x]:
            r, tris, mb, bpt, outs = (item.split(":") + [""] * 5)[:5]
            per.append("r%s: %s tri, %s MB, %s B/tri" % (r, fi(num(tris)), mb, bpt))
        if rc == "0":
            pair.setdefault((label, rep), {})[prog] = num(ext)
        rows.append([label, prog, np_, area, rep, rc, ext, fi(st.get("triangles")), f(st.get("wall_s")),
                     f(st.get("output_s")) if prog == "pcdm" else "-", "; ".join(per) or "-"])
        ocsv.append([label, prog, np_, area, rep, rc, ext, st.get("triangles"), st.get("wall_s"),
                    st.get("output_s"), ranks])
    H(md_table(["size", "program", "ranks", "-a", "rep", "status", "launch to exit s", "triangles",
                "mesh s", "output s", "per rank"], rows))
    H("")
    ratios = []
    for (label, rep), d in sorted(pair.items()):
        if "mesh" in d and "pcdm" in d and d["mesh"]:
            ratios.append(d["pcdm"] / d["mesh"])
            H("- %s rep %s: pcdm / mesh end to end = %.2f (goal <= 0.6)" % (label, rep, ratios[-1]))
    if ratios:
        stdout.append("Output 10M: pcdm(2)/mesh end to end %s" % ", ".join("%.2f" % x for x in ratios))
    H("")
    write_csv(os.path.join(R, "output.csv"),
              ["size", "program", "ranks", "area", "rep", "rc", "launch_to_exit_s", "triangles",
               "wall_s", "output_s", "ranks_triangles_peakmb_bpt_outputs"], ocsv)
    csvs.append("output.csv")


output_section()

# ---------------------------------------------------------------------------- problems, timing, commands
bad = [r for r in runs if not r["ok"]]
H("## Problems")
H("")
if not notes and not bad:
    H("None: every program existed and every run succeeded.")
else:
    for n in notes:
        H("* " + n)
    nmiss = sum(1 for r in bad if r["rc"] == "missing")
    if nmiss:
        H("* %d run(s) skipped because the program is missing (%s)." %
          (nmiss, ", ".join(sorted(set(r["prog"] for r in bad if r["rc"] == "missing")))))
    SIG = {"134": "SIGABRT (abort)", "137": "SIGKILL (out of memory or killed)", "139": "SIGSEGV",
           "143": "SIGTERM from outside the bench", "136": "SIGFPE"}
    for r in bad:
        if r["rc"] == "missing":
            continue
        what = r["rc"]
        if what in SIG:
            what = "exit status %s: killed by %s" % (what, SIG[what])
        elif what.startswith("timeout"):
            what = "%s: no result within the per-run time limit (hang or far too slow)" % what
        elif what.startswith("skipped-after-timeout"):
            what = "skipped: this cell timed out before"
        elif what.startswith("cut-budget"):
            what = "%s: stopped when the time budget ran out" % what
        elif what.startswith("skipped-budget"):
            what = "%s: not started, the time budget would not allow it" % what
        elif what == "nostats":
            what = "exit status 0 but no `stats:` line"
        else:
            what = "exit status %s" % what
        logs = (" (log: `%s.out`, `%s.err`)" % (r["log"], r["log"])) if r.get("log") else ""
        H("* %s %s/%s np=%d rep %s: **%s**%s" % (r["prog"], r["section"], r["label"], r["np"], r["rep"],
                                                what, logs))
H("")
H("## Time taken")
H("")
H(md_table(["section", "elapsed s"], [[s[0], s[1]] for s in sections if len(s) >= 2]))
H("")
H("## Files")
H("")
H("CSV per table: " + ", ".join("[%s](%s)" % (c, c) for c in csvs) +
  ".  Raw data: [runs.tsv](runs.tsv) (one line per run, with its full `stats:` line), "
  "[meta.txt](meta.txt); logs of every run in `logs/`.")
H("")
H("## Exact commands")
H("")
H("As run (areas as calibrated above).  In the 1M/10M scale runs each process was additionally "
  "wrapped in `/usr/bin/time -a -o FILE -f %M` (or a python getrusage shim when that is "
  "missing) to record its peak RSS; that wrapper is not shown.")
H("")
H("```")
H("\n".join(commands))
H("```")
H("")

with open(os.path.join(R, "report.md"), "w") as fh:
    fh.write("\n".join(report))

# ---------------------------------------------------------------------------- stdout summary
print()
print("Tables 2/3 (imbalanced 2:1, -a %s): ours wall s | modelled s | RSRs   [paper s | RSRs]" % areas["area_43k"])
for prog in ("pbw", "pcdm"):
    for np_ in NPS:
        c = cell.get((prog, "imb2", np_), {})
        print("  %-4s P=%d  wall %6s  modelled %6s  rsr %6s  speedup(model) %5s   [paper %5.2f s  %4d RSRs]" %
              (prog, np_, f(c.get("wall")), f(c.get("busy_max"), 3), fi(c.get("rsr")), f(c.get("model_speedup")),
               PAPER[prog]["time"][np_], PAPER[prog]["rsr"][np_]))
for conf in ("imb2", "imb1"):
    parts = []
    for r in rcsv:
        if r[0] == conf:
            parts.append("P=%d %s" % (r[1], f(r[4]) if r[4] is not None else "NA"))
    print("RSR ratio PBW/PCDM %s: %s%s" % (conf, "  ".join(parts),
                                           "   [paper P=2 8.19  P=4 6.40  P=8 6.87]" if conf == "imb2" else ""))
for r in ocsv:
    if r[1] == "pbw":
        print("Overhead pbw P=4 %s: comm_pct=%s undo_pct=%s   [paper 27 / 1]" % (r[0], f(r[10], 1), f(r[13], 1)))
for r in scsv:
    print("Scale %-3s %-8s P=%d: %s triangles, %s tri/s wall%s" %
          (r[0], r[1], r[2], fi(r[3]), fi(r[8]), (", modelled speedup %s" % f(r[10])) if r[10] else ""))
print("Report: %s" % os.path.join(R, "report.md"))


def g(prog, key):
    return cell.get((prog, "imb2", 8), {}).get(key)


pc_r, pb_r = g("pcdm", "rsr"), g("pbw", "rsr")
ratio = div(pb_r, pc_r)
ratio_s = f(ratio) if ratio is not None else ("inf" if isnum(pb_r) and pb_r > 0 and pc_r == 0 else "NA")
print("bench: pcdm_rsr_8=%s pbw_rsr_8=%s ratio_8=%s pcdm_wall_8=%s pbw_wall_8=%s "
      "pcdm_speedup_model_8=%s pbw_speedup_model_8=%s" %
      (fi(pc_r), fi(pb_r), ratio_s, f(g("pcdm", "wall"), 3), f(g("pbw", "wall"), 3),
       f(g("pcdm", "model_speedup")), f(g("pbw", "model_speedup"))))
