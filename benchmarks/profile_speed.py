"""Instructions of whole drops, by compiled function, for one tree or two (issue 34 item 4).

Run:  python benchmarks/profile_speed.py [-n 50] [--scenario FILE] [--tree DIR ...] [--keep DIR]

For each tree (default: the checkout this script is in; ``--tree /tmp/base`` adds another, e.g. a
``git archive`` of an older commit, run with ``PYTHONPATH`` pointing at it and its own numba cache),
the first ``n`` drops of the ensemble (the rows ``bench_ensemble.py`` times) run one after the other
on one thread under ``valgrind --tool=callgrind``, counted between two marker calls
(``--zero-before=getpgrp --dump-before=getsid``), after a native run that fills the tree's numba cache
for one fixed CPU target (``NUMBA_CPU_NAME=haswell``: valgrind's CPU reports other features, so numba
would otherwise compile under valgrind). Printed per tree:

* instructions a drop (load-independent: the number to compare; wall time on a shared host is not);
* per drop counts from the summaries (steps) and the answers' checksum (sum of penetrations), so two
  trees can be checked to run the same drops to the same answers;
* the compiled functions' *inclusive* and *self* instructions (``callgrind_annotate --inclusive``),
  with numba's mangled names shortened to ``module.function``: the kernels that are compile units of
  their own (``kernel``); those inlined into their callers (``small_kernel``, and what LLVM inlines)
  count in their caller; libm's ``sin``/``cos``/``atan2``/``asinh``/``exp`` show as their own rows.

The worker part (``--worker``) loads the ensemble with the tree's own code, so the same script runs
on an old tree as long as ``load_ensemble``, ``chunk_inputs`` and ``stepper.run_drop`` keep their
signatures (true since issue 19).
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

#: frames around the compiled code (the process, the interpreter's call into numba's dispatcher)
SKIP = {
    "main",
    "clone",
    "start_thread",
    "__libc_start_main",
    "__libc_start_call_main",
    "_start",
    "run_mod",
    "Dispatcher_call(Dispatcher*,",
    "call_cfunc(Dispatcher*,",
    "0x0000000000000000",
}
HERE = os.path.dirname(os.path.abspath(__file__))
CPU_NAME = "haswell"
CPU_FEATURES = (
    "+64bit,+avx,+avx2,+bmi,+bmi2,+cmov,+cx16,+f16c,+fma,+fxsr,+lzcnt,+mmx,+movbe,+popcnt,+sse,+sse2,+sse3,"
    "+sse4.1,+sse4.2,+ssse3,+xsave"
)


def _stash_object_code():
    """Keep the machine code of each kernel numba loads from its cache (numba drops it once loaded), so
    that the worker can name the functions in it (``function_map``)."""
    import numba.core.codegen as cg

    stash = {}
    orig = cg.CPUCodeLibrary._unserialize.__func__

    def unserialize(cls, codegen, state):
        lib = orig(cls, codegen, state)
        if state[1] == "object":
            stash[id(lib)] = state[2][0]
        return lib

    cg.CPUCodeLibrary._unserialize = classmethod(unserialize)
    return stash


def function_map(dispatcher, stash):
    """{address: short name} of every function in the machine code of ``dispatcher``'s overloads (what
    it calls is linked into it: the compile units of ``kernel``; ``small_kernel`` is inlined)."""
    return {start: name for start, _, name in function_ranges(dispatcher, stash)}


def function_ranges(dispatcher, stash):
    """(address, size in bytes, short name) of every function in the machine code of ``dispatcher``'s
    overloads (:func:`function_map`; ``profile_time.py`` places its samples with the sizes)."""
    ranges = []
    for cres in dispatcher.overloads.values():
        lib = cres.library
        obj = getattr(lib, "_compiled_object", None) or stash.get(id(lib))
        if obj is None:
            continue
        with tempfile.NamedTemporaryFile(suffix=".o") as fh:
            fh.write(obj)
            fh.flush()
            out = subprocess.run(
                ["readelf", "-sW", fh.name], capture_output=True, text=True, check=True
            ).stdout
        syms = [ln.split() for ln in out.splitlines() if " FUNC " in ln]
        entry = cres.fndesc.llvm_func_name
        base = None
        for s in syms:
            if s[7] == entry:
                base = lib.get_pointer_to_function(entry) - int(s[1], 16)
                sec = s[6]
        if base is None:
            continue
        for s in syms:
            if s[6] == sec:
                ranges.append((base + int(s[1], 16), int(s[2]), _short(s[7])))
    return ranges


def _batch_paths(P, sediment_bank):
    """``run_drop``'s ``reference_paths`` argument as the ensemble's batch passes it: the shape's
    prototype body (a frustum runs as a frustum) and the bounded overburden rule of a long table
    (``overburden.with_long_tables``); ``None`` on a tree older than those (the default paths)."""
    try:
        from mineburial.kernels.mine.overburden import with_long_tables
        from mineburial.kernels.mine.stepper import reference_paths
    except ImportError:
        return None
    return with_long_tables(reference_paths(P), P, sediment_bank)


class Drops:
    """The first ``n`` valid drops of a tree's ensemble, ready for its ``stepper.run_drop`` (the tree on
    ``sys.path``): ``run(i)`` runs drop i into ``S[i]``; ``penetrations()`` their sum. The first drop runs
    once on construction, so that the kernels are compiled or loaded from the cache before any measurement.
    Shared by this script's worker and those of ``ab_cores.py`` and ``profile_time.py``; works on trees back
    to issue 34's baseline d0a06f4."""

    def __init__(self, scenario, n):
        from mineburial.ensembles.engine import load_ensemble
        from mineburial.kernels.mine.layout import N_SUMMARY, SUMMARY_INDEX
        from mineburial.kernels.mine.stepper import run_drop

        try:
            from mineburial.systems.mine.ensemble import chunk_inputs
        except ImportError:  # a tree before the systems package (d0a06f4)
            from mineburial.ensembles.engine import chunk_inputs

        spec = load_ensemble(scenario)
        P, valid, _ = chunk_inputs(spec, 0, n)
        self.P = P[valid.astype(bool)]
        self.sb = np.ascontiguousarray(spec.sediment_bank)
        self.cb = np.ascontiguousarray(spec.current_bank)
        self.S = np.empty((len(self.P), N_SUMMARY))
        self.names = list(SUMMARY_INDEX)
        self.run_drop = run_drop
        self.paths = _batch_paths(self.P, self.sb)
        self.run(0)

    def __len__(self):
        return len(self.P)

    def run(self, i):
        self.run_drop(self.P[i], self.sb, self.cb, self.S[i], None, 1.0, self.paths)

    def penetrations(self):
        return float(np.nansum(self.S[:, self.names.index("penetration_depth")]))


def worker(args):
    stash = _stash_object_code()  # before the kernels load
    import mineburial

    drops = Drops(args.scenario, args.n)
    P, S, run_drop = drops.P, drops.S, drops.run_drop
    os.getpgrp()  # callgrind: --zero-before=getpgrp
    for i in range(len(drops)):
        drops.run(i)
    os.getsid(0)  # callgrind: --dump-before=getsid
    fmap = function_map(run_drop, stash)
    np.savez(
        args.result,
        P=P,
        S=S,
        names=np.array(drops.names),
        where=mineburial.__file__,
        faddr=np.array(list(fmap), dtype=np.uint64),
        fname=np.array(list(fmap.values())),
    )


def _short(name):
    """numba's mangled name -> module.function (the mangled scope's last two parts)."""
    m = re.match(r"_ZN(.*)", name)
    if not m:
        return name
    parts = []
    s = m.group(1)
    while s and s[0].isdigit():
        k = re.match(r"(\d+)", s).group(1)
        n = int(k)
        parts.append(s[len(k) : len(k) + n])
        s = s[len(k) + n :]
    parts = [re.sub(r"_24", "$", q) for q in parts]
    parts = [q for q in parts if q and not q.startswith("$")]
    fn = [q for q in parts if not q.startswith("_3clocals") and "dyn" not in q]
    return ".".join(fn[-2:]) if fn else name


def annotate(cgfile, top, fmap):
    """Inclusive and self Ir of each function of one callgrind dump: {short name: [incl, self]}; the JIT
    code's functions (callgrind names them by address) named by ``fmap``; frames of CPython and of the
    process set-up left out."""
    out = {}
    for inclusive in (True, False):
        txt = subprocess.run(
            ["callgrind_annotate", f"--inclusive={'yes' if inclusive else 'no'}", "--threshold=100", cgfile],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        for line in txt.splitlines():
            m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(\S+?):(\S+)", line) or re.match(
                r"\s*([\d,]+)\s+(\S+?):(\S+)", line
            )
            if not m:
                continue
            ir = int(m.group(1).replace(",", ""))
            fn = m.group(3).split(" ")[0].split("'")[0]  # f'2: f in a recursion cycle
            if fn.startswith("0x"):
                if int(fn, 16) not in fmap:
                    continue
                key = fmap[int(fn, 16)]
            elif fn.startswith("_ZN"):
                key = _short(fn)
            else:
                key = fn.split("@")[0]
                if "Py" in key or key in SKIP or key.startswith("("):
                    continue
            slot = out.setdefault(key, [0, 0])
            if inclusive:  # a name held by two functions (an entry and its wrapper): the outer one
                slot[0] = max(slot[0], ir)
            else:
                slot[1] += ir
    return dict(sorted(out.items(), key=lambda kv: -kv[1][0])[:top])


def _name(fn, fmap):
    fn = fn.split(" ")[0].split("'")[0]
    if fn.startswith("0x"):
        return fmap.get(int(fn, 16))
    return _short(fn) if fn.startswith("_ZN") else fn.split("@")[0]


def call_counts(cgfile, fmap):
    """{(caller, callee): calls} between named functions of one callgrind dump (its ``calls=`` lines)."""
    edges = {}
    cur = callee = None
    with open(cgfile) as fh:
        for line in fh:
            if line.startswith("fn="):
                cur = _name(line[3:].strip(), fmap)
            elif line.startswith("cfn="):
                callee = _name(line[4:].strip(), fmap)
            elif line.startswith("calls=") and cur and callee:
                key = (cur, callee)
                edges[key] = edges.get(key, 0) + int(line[6:].split()[0])
    return edges


#: callees whose calls are counted by caller: the right-hand side (by the integrator that asks for it:
#: dopri5 above the seabed, Rosenbrock-W with its Jacobian columns in contact), the steps, the fast
#: rule's compile units, event location and the rest test
COUNTED = (
    "_system_rhs_impl.impl",
    "derivatives.compiled_callee",
    "dopri5_step.compiled_callee",
    "ros34pw2_step.compiled_callee",
    "jacobian_columns.compiled_callee",
    "sediment_tractions.compiled_callee",
    "_lateral.compiled_callee",
    "_cap.compiled_callee",
    "_generator.compiled_callee",
    "_traction.compiled_callee",
    "locate_event.compiled_callee",
    "held_by_sediment.compiled_callee",
)


def measure(tree, args, folder):
    env = dict(
        os.environ,
        PYTHONPATH=tree,
        NUMBA_NUM_THREADS="1",
        NUMBA_CPU_NAME=CPU_NAME,
        NUMBA_CPU_FEATURES=CPU_FEATURES,
    )
    base = [sys.executable, os.path.abspath(__file__), "--worker", "-n", str(args.n)]
    if args.scenario:
        base += ["--scenario", args.scenario]
    native = os.path.join(folder, "native.npz")
    subprocess.run([*base, "--result", native], check=True, env=env, cwd=tree)  # fills the cache
    cg = os.path.join(folder, "cg")
    os.makedirs(cg, exist_ok=True)
    res = os.path.join(folder, "cg.npz")
    subprocess.run(
        [
            "valgrind",
            "--tool=callgrind",
            f"--callgrind-out-file={cg}/cg.out.%p",
            "--zero-before=getpgrp",
            "--dump-before=getsid",
            "--dump-instr=no",
            "--compress-strings=no",
            *base,
            "--result",
            res,
        ],
        check=True,
        env=env,
        cwd=tree,
        stderr=subprocess.DEVNULL,
    )
    dumps = sorted(
        (
            f
            for f in os.listdir(cg)
            if re.search(r"\.\d+$", f) and "getsid" in open(os.path.join(cg, f)).read(4096)
        ),
        key=lambda f: int(f.rsplit(".", 1)[1]),
    )
    f = os.path.join(cg, dumps[-1])
    a = np.load(native)
    b = np.load(res)
    # valgrind reports its own CPU features, so glibc's libm may pick another variant (FMA or not) of sin,
    # exp, ... than the native run (seen on an Intel host): answers then differ at rounding level only
    if not np.array_equal(a["S"], b["S"], equal_nan=True):
        diff = np.nanmax(np.abs(a["S"][:, 0] - b["S"][:, 0]))
        steps = [x["S"][:, list(x["names"]).index("n_steps")] for x in (a, b)]
        moved = int(np.count_nonzero(steps[0] != steps[1]))
        # a rounding difference can move a step of a drop near a threshold (an event, a rejection): the
        # profile still counts the same work up to those drops; report it rather than refuse
        print(
            f"note: native and callgrind answers differ by rounding (penetrations within {diff:.1e} m,"
            f" {moved} of {len(steps[0])} drops with another step count)"
        )
    fmap = dict(zip((int(x) for x in b["faddr"]), (str(x) for x in b["fname"])))
    funcs = annotate(f, args.top, fmap)
    total = funcs["stepper.run_drop"][0]  # the drops' instructions: the calls of run_drop between the marks
    return total, funcs, a, call_counts(f, fmap)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=50, help="drops (the ensemble's first n)")
    ap.add_argument("--scenario", default=None)
    ap.add_argument("--tree", action="append", default=None, help="a tree to measure (repeatable)")
    ap.add_argument("--top", type=int, default=40, help="functions listed")
    ap.add_argument("--keep", help="folder for the callgrind files")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--result", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return worker(args)
    trees = args.tree or [os.path.dirname(HERE)]
    folder = args.keep or tempfile.mkdtemp(prefix="mb-speed-")
    results = []
    for k, tree in enumerate(trees):
        sub = os.path.join(folder, f"tree{k}")
        os.makedirs(sub, exist_ok=True)
        total, funcs, a, edges = measure(os.path.abspath(tree), args, sub)
        S, names = a["S"], list(a["names"])
        steps = S[:, names.index("n_steps")]
        pen = S[:, names.index("penetration_depth")]
        nd = len(S)
        print(f"\n## {tree} ({a['where']}), {nd} drops, scenario {args.scenario or 'embedded default'}\n")
        print(f"instructions: {total:,} ({total / nd / 1e6:.2f} M a drop)")
        print(f"steps a drop: {steps.mean():.1f}; sum of penetrations: {np.nansum(pen):.12g} m")
        print("\n| function | inclusive Ir a drop | share | self Ir a drop |\n|---|---|---|---|")
        for name, (inc, own) in funcs.items():
            print(f"| `{name}` | {inc / nd:,.0f} | {100.0 * inc / total:.1f} % | {own / nd:,.0f} |")
        print("\n| calls a drop of | by | calls |\n|---|---|---|")
        for callee in COUNTED:
            for (caller, cal), n in sorted(edges.items(), key=lambda kv: -kv[1]):
                if cal == callee and caller != callee:
                    print(f"| `{callee}` | `{caller}` | {n / nd:,.1f} |")
        results.append((tree, total, nd, pen))
    if len(results) == 2:
        (ta, xa, na, pa), (tb, xb, nb, pb) = results
        same = len(pa) == len(pb) and np.array_equal(pa, pb, equal_nan=True)
        print(
            f"\n{tb} against {ta}: instructions a drop {100.0 * ((xb / nb) / (xa / na) - 1.0):+.2f} %; "
            f"penetrations {'bit-identical' if same else 'differ'}"
        )
    if not args.keep:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
