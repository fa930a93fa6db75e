#!/usr/bin/env python3
"""The half-space's bias against the number of passes (issue 56), from bench/halfspace_passes.sh's runs.

    python3 bench/halfspace_passes.py OUT [VARIANT ...]      (OUT as given to halfspace_passes.sh)
    python3 bench/halfspace_passes.py OUT --reference OUT/ref.passes.csv [VARIANT ...]   (bench/cube_passes.sh)

For each variant (a directory OUT/VARIANT of runs sSEED.passes.csv / sSEED.json, independent seeds) and
N in 64, 128, 256: the N-pass image mean (a run's first N passes; a pass's radius depends on its index
alone, so they are an N-pass run) against Chandrasekhar's closed form, mean +- SE over the seeds, and the
RMS error of one N-pass run; then the passes in the bins 0-63, 64-127, 128-255 (independent passes: the
bias of the passes themselves, not of the running mean).

Model columns (labelled as such): the bias of pass i as smoothing + clustering with
  smoothing(k_i, s_i) = S32 * s_i^p * E[T^(p/3)]_{T ~ Gamma(k_i - 1)} / E[T^(p/3)]_{T ~ Gamma(31)}
(the kNN mean is the fixed-radius mean F at the radius of a Gamma(k - 1) count, docs/walk_correlation.md
section 6, with F ~ r^p and the count ~ r^3), S32 = +1.36% (k 32, measured and derived), p = 2 (the
leading order the schedule is built for: smoothing ~ m_i^(2/3)) or p = 0.97 (the renderer's fixed radii:
+0.76% at 0.5, +1.34% at 0.9); clustering(k) = 0.73% (k / 32)^-0.71 (the walk clustering measured at k 32
and k 8, +0.73% and +1.95%, interpolated as a power law; below k 8 an extrapolation, and independent of s,
which is not known). A variant whose name holds "walks" (photons.neighbours = "walks") has no clustering
term and the walk ball's smoothing, W32 = +1.62% at k 32 (derived, section 6), for S32.

With --reference (a path-traced run's passes.csv: its mean image mean is the truth, its SE over passes is
printed) the model columns are replaced by the schedule's own prediction for a smoothing bias ~ r^2: the
fixed variant's measured bias times the mean of m_i^(2/3) over the passes (docs/progressive.md section 1).
"""
import csv, json, math, os, sys

CLOSED = 0.031147627
S32, W32, C32, C_EXP = 1.36, 1.62, 0.73, math.log(1.95 / 0.73) / math.log(32 / 8)
NS = (64, 128, 256)
BINS = ((0, 64), (64, 128), (128, 256))


def gamma_moment(a, q):   # E[T^q], T ~ Gamma(a, 1)
    return math.exp(math.lgamma(a + q) - math.lgamma(a))


def smoothing(k, s, p, base=S32):
    return base * s ** p * gamma_moment(k - 1, p / 3) / gamma_moment(31, p / 3)


def clustering(k):
    return C32 * (k / 32) ** -C_EXP


def mean_se(v):
    n = len(v); m = sum(v) / n
    return m, math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1) / n) if n > 1 else float("nan")


def load(d):
    runs = []
    for f in sorted(os.listdir(d)):
        if not f.endswith(".passes.csv"): continue
        rows = list(csv.DictReader(open(os.path.join(d, f))))
        if len(rows) < max(NS):
            print(f"{d}/{f}: {len(rows)} passes, fewer than {max(NS)}: left out", file=sys.stderr)
            continue
        x = [float(r["image_mean"]) for r in rows]
        radii = json.load(open(os.path.join(d, f.replace(".passes.csv", ".json"))))["photons"].get("radii", {})
        runs.append((x, radii, f))
    return runs


def measure_ratio(i, alpha=4 / 7):   # m_i of docs/progressive.md section 1
    return math.exp(math.lgamma(i + 1 + alpha) - math.lgamma(1 + alpha) - math.lgamma(i + 2))


def main():
    global CLOSED
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    reference = None
    if "--reference" in args:
        j = args.index("--reference"); reference = args[j + 1]; del args[j:j + 2]
        x = [float(r["image_mean"]) for r in csv.DictReader(open(reference))]
        CLOSED, se = mean_se(x)
        print(f"reference {reference}: image mean {CLOSED:.7g} +- {se / CLOSED * 100:.3f}% ({len(x)} passes)\n")
    out = args[0]
    variants = args[1:] or sorted(v for v in os.listdir(out) if os.path.isdir(os.path.join(out, v)))
    truth = "closed form" if reference is None else "reference"
    models = "model p = 2 | model p = 0.97" if reference is None else "fixed x mean m_i^(2/3) | (same)"
    print(f"| variant | passes | seeds | image mean - {truth} (mean +- SE over seeds) | RMS error of one run | {models} |")
    print("|---|---|---|---|---|---|---|")
    bins = []
    fixed_bias = float("nan")
    models_of = {}
    if reference is not None:
        variants = sorted(variants, key=lambda v: v != "fixed")   # fixed first: the other rows' model uses it
    for v in variants:
        runs = load(os.path.join(out, v))
        if len(runs) < 2: continue
        radii = runs[0][1]
        ks = radii.get("k") or [32] * max(NS)
        ss = radii.get("volume_scale") or [1.0] * max(NS)
        def model(a, b, p, v=v, ks=ks, ss=ss):
            if reference is not None:   # fixed's bias times the mean of m_i^(2/3) (an r^2 smoothing)
                return fixed_bias * sum(measure_ratio(i) ** (2 / 3) if v != "fixed" else 1.0 for i in range(a, b)) / (b - a)
            if "walks" in v:
                return sum(smoothing(ks[i], ss[i], p, W32) for i in range(a, b)) / (b - a)
            return sum(smoothing(ks[i], ss[i], p) + clustering(ks[i]) for i in range(a, b)) / (b - a)
        models_of[v] = model
        if v == "fixed":
            fixed_bias = mean_se([(sum(x[:max(NS)]) / max(NS) / CLOSED - 1) * 100 for x, _, _ in runs])[0]
        for n in NS:
            e = [(sum(x[:n]) / n / CLOSED - 1) * 100 for x, _, _ in runs]
            m, se = mean_se(e)
            rms = math.sqrt(sum(a * a for a in e) / len(e))
            print(f"| {v} | {n} | {len(runs)} | {m:+.2f}% +- {se:.2f}% | {rms:.2f}% | {model(0, n, 2):+.2f}% | {model(0, n, 0.97):+.2f}% |")
        for a, b in BINS:
            e = [(sum(x[a:b]) / (b - a) / CLOSED - 1) * 100 for x, _, _ in runs]
            m, se = mean_se(e)
            kr = f"{ks[b - 1]}-{ks[a]}" if ks[a] != ks[b - 1] else f"{ks[a]}"
            sr = f"{min(ss[a:b]):.2f}-{max(ss[a:b]):.2f}"
            bins.append(f"| {v} | {a}-{b - 1} | {kr} | {sr} | {m:+.2f}% +- {se:.2f}% | {model(a, b, 2):+.2f}% | {model(a, b, 0.97):+.2f}% |")
        d = [((sum(x[:256]) / 256 - sum(x[:64]) / 64) / CLOSED) * 100 for x, _, _ in runs]
        m, se = mean_se(d)
        bins.append(f"| {v} | 256-pass mean - 64-pass mean (paired) | | | {m:+.2f}% +- {se:.2f}% | {model(0, 256, 2) - model(0, 64, 2):+.2f}% | {model(0, 256, 0.97) - model(0, 64, 0.97):+.2f}% |")
    # The variants share the seeds (render.seed 1..SEEDS: the same photon maps), so their differences are paired.
    print()
    print(f"| variant - the first named | passes | seeds | difference (paired by seed) | {models} |")
    print("|---|---|---|---|---|---|")
    base = {f: x for x, _, f in load(os.path.join(out, variants[0]))}
    m0 = models_of.get(variants[0])
    for v in variants[1:]:
        mv = models_of.get(v)
        def dm(a, b):
            if not (m0 and mv): return "| |"
            return f"{mv(a, b, 2) - m0(a, b, 2):+.2f}% | {mv(a, b, 0.97) - m0(a, b, 0.97):+.2f}% |"
        runs = [(x, base[f]) for x, _, f in load(os.path.join(out, v)) if f in base]
        if len(runs) < 2: continue
        for n in NS:
            m, se = mean_se([(sum(x[:n]) - sum(y[:n])) / n / CLOSED * 100 for x, y in runs])
            print(f"| {v} - {variants[0]} | {n} | {len(runs)} | {m:+.2f}% +- {se:.2f}% | {dm(0, n)}")
        for a, b in BINS:
            m, se = mean_se([(sum(x[a:b]) - sum(y[a:b])) / (b - a) / CLOSED * 100 for x, y in runs])
            print(f"| {v} - {variants[0]} | {a}-{b - 1} | {len(runs)} | {m:+.2f}% +- {se:.2f}% | {dm(a, b)}")
    print()
    print(f"| variant | passes | k | s | mean of these passes - {truth} | {models} |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(bins))


main()
