#!/usr/bin/env python3
"""Trains canopy's learned view scorer (issue 47) from candidate audits, and ranks it against the truth.

The candidate audit (mission.record.candidates) writes, per planning round, every candidate a
planner scored with its view features (nbv/view_features.h: columns f:<name>) and its truth score
(the uncovered true fruit surface points it sees). One round is one query; the model orders its
candidates (XGBoost learning to rank, gradient-boosted trees).

    python3 tools/train_view_ranker.py runs/ranker_default runs/ranker_dense --out model.json

(The model in the tree, models/nbv/view_ranker.json, comes from the command in docs/learned.md,
"Training data and the command", with its flags and four audits.)

Only tuning worlds train: a trial whose world seed is 1000 or more (the evaluation worlds) is
refused, one line and exit 2. --evaluate RUN... ranks the model against the truth on other runs
(the evaluation worlds allowed there) beside every hand-made gain, as canopy report's
gain_truth table does: per round Spearman's rho, the top view being the truth's best (top-1) or
in its best five (top-5), the truth rank of the top view, the score's rank of the truth's best
view, and the top view's share of the round's best truth; means over rounds, one table per run.
--model FILE ranks a model already trained instead of training one (no training runs then):

    python3 tools/train_view_ranker.py --model models/nbv/view_ranker.json --evaluate runs/learned_eval

--cv chooses the model's settings on the tuning worlds alone: for each world seed, a model trained
on the other seeds' rounds ranks that seed's rounds (docs/learned.md, "Choosing the model"):

    python3 tools/train_view_ranker.py runs/ranker_default runs/ranker_dense --methods ours shape reveal --cv

--cv-hold SEEDS ranks only those worlds, and --train-worlds N trains each of their models on the N
lowest other world seeds only: a learning curve (docs/learned.md, "Is data the limit?").

--fruit-value (with --fruit-maxima) trains two models: a fruit-value model, gradient-boosted
regression trees from a fruit's maxima to the share of the round's best truth that the fruit's best
candidate sees, and the ranker with that estimate as one more input (fruit_value). The ranker's
training rounds get the estimate out of fold (from models that did not see their world); the
fruit-value model written beside the ranker (X.fruit_value.json for --out X.json) is fitted on
every training round. Both carry the same canopy_pair attribute; nbv::ViewRanker and --model read
the pair and refuse a ranker without its own fruit-value model.

--p-gt P... trains (or cross-validates) on the rounds of trials with those segmentation accuracies
only: a model for a clean or a noisy segmentation alone (docs/learned.md: tried, not taken).

--drop-features NAME... trains without some recorded features (an ablation). A model reads its
features by name: --evaluate runs may record more features than it names.
"""
import argparse
import csv
import glob
import hashlib
import json
import math
import os
import sys

import numpy as np

TUNING_SEED_LIMIT = 1000


def fail(msg):
    print(f"train_view_ranker: {msg}", file=sys.stderr)
    sys.exit(2)


def trials_of(run):
    """(trial folder, trial record) of every ok trial with a candidates.csv under an experiment folder."""
    out = []
    for tj in sorted(glob.glob(os.path.join(run, "trials", "*", "trial.json"))):
        folder = os.path.dirname(tj)
        with open(tj) as f:
            t = json.load(f)
        cands = os.path.join(folder, "mission", "candidates.csv")
        if t.get("status") != "ok" or not os.path.exists(cands):
            continue
        out.append((folder, t))
    return out


def read_rounds(runs, tuning_only):
    """Rounds of every trial: list of dicts with the features matrix, truth, audit scores and the trial's keys."""
    rounds = []
    names = None
    scores_names = None
    for run in runs:
        trials = trials_of(run)
        if not trials:
            fail(f"{run}: no trial with a candidates.csv (run it with mission.record.candidates: true)")
        for folder, t in trials:
            spec = t["trial"]
            seed = spec.get("world_seed")
            if tuning_only and (seed is None or seed >= TUNING_SEED_LIMIT):
                fail(f"{folder}: world seed {seed} is an evaluation world (>= {TUNING_SEED_LIMIT}); train on tuning worlds only")
            path = os.path.join(folder, "mission", "candidates.csv")
            with open(path) as f:
                rows = list(csv.reader(f))
            header = rows[0]
            feats = [i for i, h in enumerate(header) if h.startswith("f:")]
            if not feats:
                fail(f"{path}: no feature columns (f:...): recorded by an older canopy")
            fnames = [header[i][2:] for i in feats]
            if names is None:
                names = fnames
            elif fnames != names:
                fail(f"{path}: its features differ from the first file's (recorded by another canopy)")
            first_score = header.index("truth") + 1
            snames = header[first_score:feats[0]]
            scores_names = scores_names or snames
            ci = {h: i for i, h in enumerate(header)}
            group = {}
            order = []
            for r in rows[1:]:
                if not r:
                    continue
                key = (r[ci["stop"]], r[ci["round"]])
                if key not in group:
                    group[key] = []
                    order.append(key)
                group[key].append(r)
            world = os.path.basename(os.path.normpath(run))
            for key in order:
                rs = group[key]
                if len(rs) < 2:
                    continue
                X = np.array([[float(r[i]) for i in feats] for r in rs], dtype=np.float32)
                truth = np.array([float(r[ci["truth"]]) for r in rs])
                planner = np.array([float(r[ci["planner_gain"]]) for r in rs])
                S = np.array([[float(r[ci[n]]) for n in snames] for r in rs]) if snames else np.zeros((len(rs), 0))
                cluster = np.array([int(r[ci["cluster"]]) for r in rs]) if "cluster" in ci else None
                rounds.append({"X": X, "truth": truth, "planner": planner, "scores": S, "cluster": cluster, "run": world,
                               "method": spec["label"], "p_gt": spec["p_gt"], "world_seed": seed,
                               "trial": spec["id"]})
    return rounds, names, scores_names


FRUIT_SUFFIX = "@fruit"


def fruit_maxima(X, cluster):
    """Each candidate's fruit maxima: per feature, the largest value over the round's candidates
    aimed at the same fruit (`cluster`), NaN ignored (NaN when all are): as nbv::ViewRanker computes them."""
    F = np.empty_like(X)
    for c in np.unique(cluster):
        m = cluster == c
        F[m] = np.fmax.reduce(X[m], axis=0)
    return F


def add_fruit_maxima(rounds, names):
    """The features with each one's fruit maximum beside them (names + <name>@fruit)."""
    for r in rounds:
        if r["cluster"] is None:
            fail(f"trial {r['trial']}: its candidates.csv has no cluster column (recorded by an older canopy)")
        r["X"] = np.hstack([r["X"], fruit_maxima(r["X"], r["cluster"])])
    return names + [n + FRUIT_SUFFIX for n in names]


def average_ranks(v):
    order = np.argsort(v, kind="mergesort")
    ranks = np.empty(len(v))
    sv = v[order]
    i = 0
    while i < len(v):
        j = i
        while j + 1 < len(v) and sv[j + 1] == sv[i]:
            j += 1
        ranks[order[i:j + 1]] = (i + j) / 2.0 + 1.0
        i = j + 1
    return ranks


def spearman(a, b):
    ra, rb = average_ranks(a), average_ranks(b)
    if np.std(ra) == 0 or np.std(rb) == 0:
        return None
    return float(np.corrcoef(ra, rb)[0, 1])


class Agreement:
    """The same statistics as evaluation::RankAgreement (rank_stats.h)."""

    def __init__(self):
        self.rounds = self.correlated = self.top1 = self.top5 = self.share_rounds = 0
        self.rho = self.rank = self.share = self.best_rank = 0.0

    def add(self, score, truth):
        self.rounds += 1
        rho = spearman(score, truth)
        if rho is not None:
            self.correlated += 1
            self.rho += rho
        choice = int(np.argmax(score))  # the first largest
        rank = 1 + int(np.sum(truth > truth[choice]))
        self.top1 += rank == 1
        self.top5 += rank <= 5
        self.rank += rank
        # The truth's best view (the first of them) in the score's order: 1 + views scored above it
        # + half the others scored alike (a score that ties everything ranks it in the middle).
        b = score[int(np.argmax(truth))]
        self.best_rank += 1 + int(np.sum(score > b)) + 0.5 * (int(np.sum(score == b)) - 1)
        best = truth.max()
        if best > 0:
            self.share += truth[choice] / best
            self.share_rounds += 1

    def row(self):
        n = max(self.rounds, 1)
        return (self.rounds, self.rho / max(self.correlated, 1), self.top1 / n, self.top5 / n, self.rank / n,
                self.share / max(self.share_rounds, 1), self.best_rank / n)


def relevance(truth):
    """Graded relevance of a round's candidates for rank:ndcg: 0..10 by the share of the round's best truth."""
    best = truth.max()
    if best <= 0:
        return np.zeros_like(truth)
    return np.round(10.0 * truth / best)


def train(rounds, names, args):
    import xgboost as xgb
    X = np.concatenate([r["X"] for r in rounds])
    y = np.concatenate([relevance(r["truth"]) for r in rounds])
    d = xgb.DMatrix(X, label=y, feature_names=names, missing=np.nan)
    d.set_group([len(r["truth"]) for r in rounds])
    params = {"objective": args.objective, "eta": args.eta, "max_depth": args.depth, "min_child_weight": 1.0,
              "subsample": 0.8, "colsample_bytree": 0.8, "seed": args.seed, "nthread": args.threads,
              "eval_metric": "ndcg@5"}
    return xgb.train(params, d, num_boost_round=args.trees)


def predict(booster, rounds, names, cols=None):
    """Each round's model scores (one matrix for every round: the same numbers as round by round);
    `cols`: the columns of the rounds' features the model's `names` are (all, in order, when None)."""
    import xgboost as xgb
    if not rounds:
        return
    X = np.concatenate([r["X"] for r in rounds])
    if cols is not None:
        X = X[:, cols]
    y = booster.predict(xgb.DMatrix(X, feature_names=names, missing=np.nan))
    at = 0
    for r in rounds:
        r["model"] = y[at:at + len(r["truth"])]
        at += len(r["truth"])


FRUIT_VALUE = "fruit_value"  # nbv::ViewRanker::kFruitValue


def fruit_inputs(names):
    """The fruit-value model's inputs: the fruit maxima among `names`."""
    return [n for n in names if n.endswith(FRUIT_SUFFIX)]


def fruit_rows(rounds, cols):
    """Per round and fruit: the round, its candidates of that fruit, the fruit's inputs (columns `cols`
    of the rounds' features: fruit maxima, the same for each of its candidates) and its target: the
    share of the round's best truth that its best candidate sees."""
    rows = []
    for ri, r in enumerate(rounds):
        best = r["truth"].max()
        for c in np.unique(r["cluster"]):
            m = np.nonzero(r["cluster"] == c)[0]
            rows.append((ri, m, r["X"][m[0], cols], r["truth"][m].max() / best if best > 0 else 0.0))
    return rows


def fit_fruit_value(rows, fnames, args):
    """The fruit-value model: gradient-boosted regression trees from a fruit's maxima to its target."""
    import xgboost as xgb
    X = np.array([x for _, _, x, _ in rows], dtype=np.float32)
    y = np.array([t for _, _, _, t in rows], dtype=np.float32)
    params = {"objective": "reg:squarederror", "eta": 0.05, "max_depth": 6, "subsample": 0.8,
              "colsample_bytree": 0.8, "seed": args.seed, "nthread": args.threads}
    return xgb.train(params, xgb.DMatrix(X, label=y, feature_names=fnames, missing=np.nan), num_boost_round=200)


def set_fruit_value(model, rounds, rows):
    """The fruit-value model's estimate of each of `rows` (fruit_rows of `rounds`) written to its
    candidates' fruit_value (r["fv"])."""
    import xgboost as xgb
    if not rows:
        return
    X = np.array([x for _, _, x, _ in rows], dtype=np.float32)
    for (ri, m, _, _), v in zip(rows, model.predict(xgb.DMatrix(X, feature_names=model.feature_names, missing=np.nan))):
        rounds[ri]["fv"][m] = v


def apply_fruit_value(model, rounds, names):
    """Each round's fruit_value column (r["fv"]): the fruit-value model's estimate for each candidate's
    fruit from the fruit maxima it names, found by name among the rounds' `names`."""
    at = {n: i for i, n in enumerate(names)}
    missing = [n for n in model.feature_names if n not in at]
    if missing:
        fail(f"no feature {missing[0]} in the runs' candidates.csv, which the fruit-value model reads")
    for r in rounds:
        r["fv"] = np.zeros(len(r["truth"]), dtype=np.float32)
    set_fruit_value(model, rounds, fruit_rows(rounds, [at[n] for n in model.feature_names]))


def with_fruit_value(rounds, names):
    """The rounds' features with their fruit_value column beside them (the names, with it)."""
    for r in rounds:
        r["X"] = np.hstack([r["X"], r["fv"][:, None]])
    return names + [FRUIT_VALUE]


def fit_fruit_values(rounds, names, args):
    """The fruit-value model of training rounds, fitted on all of them (the one shipped beside the
    ranker), and each round's fruit_value out of fold, by a model that did not see its world: the
    training worlds in four groups (by seed, in turn), each group's rounds estimated by a model fitted
    on the other groups'. The ranker then learns how far to trust the estimate on unseen worlds."""
    seeds = sorted({r["world_seed"] for r in rounds})
    if len(seeds) < 2:
        fail("--fruit-value needs rounds of two training worlds or more (its estimates are out of fold)")
    fnames = fruit_inputs(names)
    rows = fruit_rows(rounds, [names.index(n) for n in fnames])
    for r in rounds:
        r["fv"] = np.zeros(len(r["truth"]), dtype=np.float32)
    for g in [set(seeds[i::4]) for i in range(min(4, len(seeds)))]:
        held = [row for row in rows if rounds[row[0]]["world_seed"] in g]
        set_fruit_value(fit_fruit_value([row for row in rows if rounds[row[0]]["world_seed"] not in g], fnames, args),
                        rounds, held)
    return fit_fruit_value(rows, fnames, args)


def load_model(path, what):
    import xgboost as xgb
    if not os.path.isfile(path):
        fail(f"{path}: no such {what} file")
    booster = xgb.Booster()
    try:
        booster.load_model(path)
    except xgb.core.XGBoostError as e:
        fail(f"{path}: not an XGBoost model ({str(e).splitlines()[0]})")
    if not booster.feature_names:
        fail(f"{path}: the model names no features")
    return booster


def paired_fruit_model(booster, path):
    """The fruit-value model a ranker reading fruit_value names beside it (None when it reads none),
    refused as nbv::ViewRanker refuses it."""
    if FRUIT_VALUE not in booster.feature_names:
        return None
    file = booster.attr("canopy_fruit_value")
    if not file or "/" in file:
        fail(f"{path}: it reads {FRUIT_VALUE} but names no fruit-value model file beside it")
    fruit_path = os.path.join(os.path.dirname(path), file)
    fruit = load_model(fruit_path, "fruit-value model")
    if not booster.attr("canopy_pair") or booster.attr("canopy_pair") != fruit.attr("canopy_pair"):
        fail(f"{path}: it was not trained with the fruit-value model {fruit_path}")
    return fruit


def save_atomically(booster, path):
    tmp = f"{path}.tmp{os.getpid()}.json"
    booster.save_model(tmp)
    os.replace(tmp, path)


def cross_validate(rounds, names, args):
    """Model selection on the tuning worlds: for each world seed, a model trained on the other seeds'
    rounds (of --methods) ranks that seed's rounds (every method's); per run folder and P_gt, the
    rounds' mean Spearman rho, top-1, top-5 and truth share, for the rounds of each method alone and all."""
    seeds = sorted({r["world_seed"] for r in rounds})
    if len(seeds) < 2:
        fail("--cv needs rounds of two tuning worlds or more")
    held = sorted(set(args.cv_hold)) or seeds  # a seed named twice is ranked once
    unknown = sorted(set(held) - set(seeds))
    if unknown:
        fail(f"--cv-hold: no rounds of world {', '.join(map(str, unknown))} in the runs")
    trained_on = []
    for s in held:
        others = [o for o in seeds if o != s]
        if args.train_worlds:
            if args.train_worlds > len(others):
                fail(f"--train-worlds {args.train_worlds}: only {len(others)} other worlds to train on without world {s}")
            others = others[:args.train_worlds]
        trained_on.append(f"{s} by {'+'.join(map(str, others))}")
        train_rounds = [r for r in rounds if r["world_seed"] in others and (not args.methods or r["method"] in args.methods)]
        if not train_rounds:
            fail(f"--cv: no round to train on without world {s}")
        test_rounds = [r for r in rounds if r["world_seed"] == s]
        if args.fruit_value:
            apply_fruit_value(fit_fruit_values(train_rounds, names, args), test_rounds, names)
            saved = [(r, r["X"]) for r in train_rounds + test_rounds]
            fv_names = with_fruit_value(train_rounds + test_rounds, names)
            predict(train(train_rounds, fv_names, args), test_rounds, fv_names)
            for r, X in saved:
                r["X"] = X
        else:
            predict(train(train_rounds, names, args), test_rounds, names)
    rounds = [r for r in rounds if r["world_seed"] in held]
    out = [f"### Cross-validation by tuning world ({', '.join(trained_on)}): objective {args.objective}, "
           f"{args.trees} trees of depth {args.depth}, eta {args.eta}, seed {args.seed}"
           f"{', reading a fruit-value model (out of fold)' if args.fruit_value else ''}", "",
           "| runs | P_gt | rounds of | rounds | Spearman ρ | top-1 | top-5 | truth share |", "|---|---|---|---|---|---|---|---|"]
    shares = {}
    for run in sorted({r["run"] for r in rounds}):
        for p_gt in sorted({r["p_gt"] for r in rounds}, reverse=True):
            cell = [r for r in rounds if r["run"] == run and r["p_gt"] == p_gt]
            for method in sorted({r["method"] for r in cell}) + ["all"]:
                a = Agreement()
                for r in cell:
                    if method in ("all", r["method"]):
                        a.add(r["model"], r["truth"])
                n, rho, top1, top5, _, share, _ = a.row()
                if n:
                    out.append(f"| {run} | {p_gt:g} | {method} | {n} | {rho:.3f} | {top1:.1%} | {top5:.1%} | {share:.3f} |")
                    shares.setdefault(method, []).append(share)
    out += ["", "Mean truth share over the conditions: " +
            ", ".join(f"{m} {np.mean(v):.3f}" for m, v in sorted(shares.items())), ""]
    return "\n".join(out)


def ranking_table(rounds, names, scores_names, title, with_model):
    """Markdown: every score's agreement with the truth, per (P_gt), over the rounds."""
    cols = []
    if with_model:
        cols.append(("learned (model)", lambda r: r["model"]))
    cols.append(("the planner's own score", lambda r: r["planner"]))
    for j, n in enumerate(scores_names):
        cols.append((f"{n} (audit)", lambda r, j=j: r["scores"][:, j]))
    for j, n in enumerate(names):
        cols.append((n, lambda r, j=j: np.nan_to_num(r["X"][:, j], nan=-1e30)))
    out = [f"### {title}", "",
           "| P_gt | score | rounds | Spearman ρ | top-1 | top-5 | truth rank of its top view | its rank of the truth's best | truth share |",
           "|---|---|---|---|---|---|---|---|---|"]
    for pgt in sorted({r["p_gt"] for r in rounds}, reverse=True):
        rs = [r for r in rounds if r["p_gt"] == pgt]
        rows = []
        for label, f in cols:
            a = Agreement()
            for r in rs:
                a.add(f(r), r["truth"])
            rows.append((label, a.row()))
        keep = rows[:2 if with_model else 1] + sorted(rows[2 if with_model else 1:], key=lambda x: -x[1][1])
        for label, (n, rho, t1, t5, rank, share, best_rank) in keep:
            out.append(f"| {pgt:g} | {label} | {n} | {rho:.2f} | {100 * t1:.0f} % | {100 * t5:.0f} % | {rank:.1f} | "
                       f"{best_rank:.1f} | {share:.2f} |")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="*", help="experiment folders of tuning worlds (world seeds < 1000) with candidates.csv")
    ap.add_argument("--out", help="the model file (XGBoost JSON) to train")
    ap.add_argument("--model", help="rank this trained model on the --evaluate runs instead of training one")
    ap.add_argument("--evaluate", nargs="*", default=[], help="experiment folders to rank the model on (any worlds)")
    ap.add_argument("--holdout", type=int, nargs="*", default=[],
                    help="tuning world seeds kept out of training and ranked instead (model selection)")
    ap.add_argument("--methods", nargs="*", default=[],
                    help="train on the rounds of these trial labels only (e.g. ours shape reveal: the shipped model)")
    ap.add_argument("--p-gt", type=float, nargs="+", default=[], metavar="P",
                    help="only the rounds of trials with these segmentation accuracies (P_gt): a model for a segmentation "
                         "that clean or that noisy (docs/learned.md: tried, not taken)")
    ap.add_argument("--objective", default="rank:pairwise")
    ap.add_argument("--trees", type=int, default=300)
    ap.add_argument("--depth", type=int, default=6)
    ap.add_argument("--eta", type=float, default=0.05)
    ap.add_argument("--seed", type=int, default=1, help="XGBoost's seed (its row and column subsampling)")
    ap.add_argument("--cv", action="store_true",
                    help="cross-validate by tuning world instead of training a model (model selection; --table writes it)")
    ap.add_argument("--cv-hold", type=int, nargs="*", default=[],
                    help="with --cv: rank only these world seeds, each by a model trained without it (default: every seed)")
    ap.add_argument("--train-worlds", type=int, default=0,
                    help="with --cv: train each fold on the N lowest other world seeds only (a learning curve; default: all)")
    ap.add_argument("--threads", type=int, default=1, help="1: the same model, byte for byte, from the same data")
    ap.add_argument("--table", help="write the ranking tables (markdown) here")
    ap.add_argument("--fruit-value", action="store_true",
                    help="with --fruit-maxima: also train a fruit-value model (a regressor from a fruit's maxima to the "
                         "share of the round's best truth its best view sees) and give the ranker its estimate as one "
                         "more input, fruit_value; --out X.json writes it beside as X.fruit_value.json")
    ap.add_argument("--drop-features", nargs="*", default=[], metavar="NAME",
                    help="train without these recorded features (and their fruit maxima): an ablation")
    ap.add_argument("--fruit-maxima", action="store_true",
                    help="also each feature's largest value over the round's candidates aimed at the same fruit "
                         "(<name>@fruit; nbv::ViewRanker computes them for a model that names them)")
    args = ap.parse_args()
    if (args.cv_hold or args.train_worlds) and not args.cv:
        fail("--cv-hold and --train-worlds go with --cv")
    if args.fruit_value and not args.fruit_maxima:
        fail("--fruit-value goes with --fruit-maxima (the fruit-value model reads the fruit maxima)")
    if args.train_worlds < 0:
        fail("--train-worlds: give a number of worlds, 0 or more (0: every other world)")

    if args.model:
        if args.runs or args.out or args.holdout or args.p_gt or not args.evaluate:
            fail("--model ranks a trained model on --evaluate runs: give neither training runs, --out, --holdout nor --p-gt")
        booster = load_model(args.model, "model")
        finish(booster, paired_fruit_model(booster, args.model), booster.feature_names, [], [], args)
        return
    if not args.runs or not (args.out or args.cv):
        fail("give the tuning runs to train on and --out or --cv (or --model with --evaluate)")
    rounds, names, scores_names = read_rounds(args.runs, tuning_only=True)
    if args.p_gt:
        missing = sorted(set(args.p_gt) - {r["p_gt"] for r in rounds})
        if missing:
            fail(f"--p-gt: no trial with P_gt {missing[0]:g} in the training runs")
        rounds = [r for r in rounds if r["p_gt"] in args.p_gt]
    if args.drop_features:
        unknown = sorted(set(args.drop_features) - set(names))
        if unknown:
            fail(f"--drop-features: no feature {unknown[0]} in the runs' candidates.csv")
        keep = [i for i, n in enumerate(names) if n not in args.drop_features]
        if not keep:
            fail("--drop-features: no feature left to train on")
        for r in rounds:
            r["X"] = r["X"][:, keep]
        names = [names[i] for i in keep]
    if args.fruit_maxima:
        names = add_fruit_maxima(rounds, names)
    missing = sorted(set(args.methods) - {r["method"] for r in rounds})
    if missing:
        fail(f"--methods: no rounds of {', '.join(missing)} in the training runs")
    if args.cv:
        if args.out or args.holdout or args.evaluate:
            fail("--cv cross-validates on the tuning runs: give neither --out, --holdout nor --evaluate")
        text = cross_validate(rounds, names, args)
        if args.table:
            with open(args.table, "w") as f:
                f.write(text)
        print(text)
        return
    if args.methods:
        rounds = [r for r in rounds if r["method"] in args.methods]
    held = [r for r in rounds if r["world_seed"] in args.holdout]
    train_rounds = [r for r in rounds if r["world_seed"] not in args.holdout]
    if not train_rounds:
        fail("no round to train on")
    fruit = None
    if args.fruit_value:
        fruit = fit_fruit_values(train_rounds, names, args)
        booster = train(train_rounds, with_fruit_value(train_rounds, names), args)
        # The pair: both models carry the fruit-value model's digest; the ranker names its file.
        pair = hashlib.sha256(fruit.save_raw("json")).hexdigest()[:16]
        fruit.set_attr(canopy_pair=pair)
        fruit_out = (args.out[:-5] if args.out.endswith(".json") else args.out) + ".fruit_value.json"
        booster.set_attr(canopy_pair=pair, canopy_fruit_value=os.path.basename(fruit_out))
        save_atomically(fruit, fruit_out)
        print(f"fruit-value model {os.path.getsize(fruit_out)} bytes: {fruit_out}")
    else:
        booster = train(train_rounds, names, args)
    save_atomically(booster, args.out)
    n_rows = sum(len(r["truth"]) for r in train_rounds)
    print(f"trained on {len(train_rounds)} rounds, {n_rows} candidates, {len(booster.feature_names)} features "
          f"({len({(r['run'], r['trial']) for r in train_rounds})} trials); model {os.path.getsize(args.out)} bytes: {args.out}")
    finish(booster, fruit, booster.feature_names, held, scores_names, args)


def finish(booster, fruit, names, held, scores_names, args):
    """Ranks the model (and its fruit-value model `fruit`, None without) on the held-out rounds and on
    each --evaluate run; prints and writes the tables."""
    tables = []
    if held:
        if fruit is not None:
            apply_fruit_value(fruit, held, [n for n in names if n != FRUIT_VALUE])
            with_fruit_value(held, [])
        predict(booster, held, names)
        tables.append(ranking_table(held, names, scores_names, f"Held-out tuning worlds {args.holdout}", True))
    for run in args.evaluate:
        ev, ev_names, ev_scores = read_rounds([run], tuning_only=False)
        if fruit is not None or any(n.endswith(FRUIT_SUFFIX) for n in names):
            ev_names = add_fruit_maxima(ev, ev_names)
        if fruit is not None:
            apply_fruit_value(fruit, ev, ev_names)
            ev_names = with_fruit_value(ev, ev_names)
        # The model reads its features by name, as nbv::ViewRanker does (an audit may record more).
        at = {n: i for i, n in enumerate(ev_names)}
        missing = [n for n in names if n not in at]
        if missing:
            fail(f"{run}: no feature {missing[0]} in its candidates.csv, which the model reads (recorded by another canopy)")
        predict(booster, ev, names, [at[n] for n in names])
        tables.append(ranking_table(ev, ev_names, ev_scores, f"{run}: every audited round of {', '.join(sorted({r['method'] for r in ev}))}", True))
    text = "\n".join(tables)
    if args.table:
        with open(args.table, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
