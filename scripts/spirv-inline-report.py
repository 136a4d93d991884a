#!/usr/bin/env python3
"""Predicts what rust-gpu 0.11's linker will inline in a SPIR-V module, and
how big the module gets after inlining (issue 9; BENCHMARKS.md "GPU").

Input: the module *before* inlining, dumped by the shader build with

    RUSTGPU_CODEGEN_ARGS="--dump-pre-inline DIR" scripts/build-spirv.sh

(DIR/boundtrace_gpu_shader.spv appears within a minute; the build may be
stopped then). The rules modelled are those of rust-gpu 0.11's
`linker/inline.rs` (read, not copied): a call is inlined when the callee
 - may panic (contains rust-gpu's custom `Abort`, or calls a function that
   may; aborts must reach the entry point to become returns),
 - returns a pointer, or takes a pointer into a storage class other than
   Function/Private/Workgroup/UniformConstant (e.g. a storage buffer), or a
   type holding a pointer (a struct with a slice or a reference inside),
 - is passed a pointer that is not a variable or a parameter of the caller
   (e.g. a pointer to a struct field), or
 - carries the `Inline` function control, which `#[inline]` gives.
Everything else stays a call. Sizes are in instructions (debug-info
instructions included), assuming each inlined body is copied whole.

usage: spirv-inline-report.py MODULE.spv [TOP]
env:   NOHINT=a,b  ignore `#[inline]` on functions whose name contains a or b
       SAFE=a,b    treat functions whose name contains a or b as panic-free
(what-if switches, to see which change would pay before making it).
"""
import collections
import os
import struct
import sys

TYPE_OPS = set(range(19, 40)) - {32}
CONST_OPS = set(range(41, 53))
LEGAL_PARAM_SC = {0, 4, 6, 7, 10}  # UniformConstant, Workgroup, Private, Function, AtomicCounter


def lit_str(words):
    raw = b"".join(struct.pack("<I", x) for x in words)
    return raw.split(b"\0")[0].decode("utf8", "replace")


def parse(path):
    data = open(path, "rb").read()
    w = struct.unpack("<%dI" % (len(data) // 4), data)
    if len(w) < 5 or w[0] != 0x07230203:
        sys.exit(f"{path}: not a SPIR-V module")
    names, funcs, entries, legal = {}, {}, [], {}
    custom_set, cur, i = None, None, 5
    while i < len(w):
        n, op = w[i] >> 16, w[i] & 0xFFFF
        if n == 0:
            sys.exit(f"{path}: malformed instruction at word {i}")
        ops = w[i + 1 : i + n]
        if op == 5:  # OpName
            names[ops[0]] = lit_str(ops[1:])
        elif op == 11 and lit_str(ops[1:]).startswith("Rust."):
            custom_set = ops[0]  # rust-gpu's custom instruction set
        elif op == 15:  # OpEntryPoint
            entries.append(ops[1])
        elif cur is None and op == 32:  # OpTypePointer: pointee must be pointer-free
            if legal.get(ops[2]) == "type":
                legal[ops[0]] = "ptr:%d" % ops[1]
        elif cur is None and op in TYPE_OPS:
            rest = ops[1:]
            if op in (28, 30, 33):  # array, struct, function: all operands
                ok = all(legal.get(x) in ("type", "const") for x in rest)
            elif op in (23, 24, 29):  # vector, matrix, runtime array
                ok = legal.get(rest[0]) in ("type", "const")
            else:
                ok = True
            if ok:
                legal[ops[0]] = "type"
        elif cur is None and op in CONST_OPS:
            if legal.get(ops[0]) == "type":
                legal[ops[1]] = "const"
        elif cur is None and op == 59:  # global OpVariable
            if legal.get(ops[0], "").startswith("ptr"):
                legal[ops[1]] = "var"
        elif op == 54:  # OpFunction
            cur = ops[1]
            funcs[cur] = dict(own=0, calls=[], params=[], ptypes=[], ret=ops[0],
                              control=ops[2], locals=set(), aborts=False)
        elif op == 55:
            funcs[cur]["params"].append(ops[1])
            funcs[cur]["ptypes"].append(ops[0])
        elif op == 56:
            cur = None
        elif cur is not None:
            f = funcs[cur]
            f["own"] += 1
            if op == 57:  # OpFunctionCall
                f["calls"].append((ops[2], list(ops[3:])))
            elif op == 59:
                f["locals"].add(ops[1])
            elif op == 12 and ops[2] == custom_set and ops[3] == 4:  # custom Abort
                f["aborts"] = True
        i += n
    return names, funcs, entries, legal


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    top = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    names, funcs, entries, legal = parse(sys.argv[1])
    nm = lambda f: names.get(f, "%" + str(f))[:140]
    split = lambda v: [x for x in os.environ.get(v, "").split(",") if x]
    nohint, safe = split("NOHINT"), split("SAFE")

    may_abort = {g for g, f in funcs.items()
                 if f["aborts"] and not any(p in nm(g) for p in safe)}
    changed = True
    while changed:
        changed = False
        for g, f in funcs.items():
            if g not in may_abort and any(c in may_abort for c, _ in f["calls"]):
                may_abort.add(g)
                changed = True

    def reason(caller, callee, args):
        f = funcs[callee]
        if callee in may_abort:
            return "may panic"
        if legal.get(f["ret"]) != "type":
            return "pointer return type"
        for t in f["ptypes"]:
            k = legal.get(t)
            if k is None:
                return "parameter type holding a pointer"
            if k.startswith("ptr") and int(k[4:]) not in LEGAL_PARAM_SC:
                return "pointer parameter into storage class %s" % k[4:]
        cf = funcs[caller]
        for t, a in zip(f["ptypes"], args):
            if legal.get(t, "").startswith("ptr") and not (
                    legal.get(a) == "var" or a in cf["locals"] or a in cf["params"]):
                return "pointer argument that is no variable"
        if f["control"] & 1 and not any(p in nm(callee) for p in nohint):
            return "#[inline]"
        return None

    # Topological order (callees first); SPIR-V has no recursion.
    order, seen = [], set()
    for root in funcs:
        stack = [(root, iter(funcs[root]["calls"]))]
        if root in seen:
            continue
        seen.add(root)
        while stack:
            g, it = stack[-1]
            nxt = next(it, None)
            if nxt is None:
                order.append(g)
                stack.pop()
            elif nxt[0] not in seen:
                seen.add(nxt[0])
                stack.append((nxt[0], iter(funcs[nxt[0]]["calls"])))
    size = {}
    for g in order:
        size[g] = funcs[g]["own"] + sum(
            size[c] for c, a in funcs[g]["calls"] if reason(g, c, a))
    # Functions that stay functions: entry points and callees of kept calls.
    kept, todo, why = set(entries), list(entries), collections.Counter()
    visited = set(entries)
    while todo:
        g = todo.pop()
        for c, a in funcs[g]["calls"]:
            r = reason(g, c, a)
            why[r or "call kept"] += 1
            if not r:
                kept.add(c)
            if c not in visited:
                visited.add(c)
                todo.append(c)
    total = sum(size[g] for g in kept)
    print(f"{len(funcs)} functions, {sum(f['own'] for f in funcs.values()):,} instructions before inlining")
    print(f"{len(may_abort)} functions may panic (directly or through a callee)")
    print(f"predicted after inlining: {total:,} instructions in {len(kept)} functions")
    for e in entries:
        print(f"  entry point {nm(e)}: {size[e]:,}")
    print("\ncall sites by inlining reason:")
    for r, c in why.most_common():
        print(f"  {c:>6}  {r}")
    # copies of each function in the inlined bodies of the kept ones
    copies = collections.Counter({k: 1 for k in kept})
    for g in reversed(order):
        for c, a in funcs[g]["calls"]:
            if reason(g, c, a):
                copies[c] += copies[g]
    print(f"\ntop {top} contributors after inlining (copies x own size):")
    rows = sorted(funcs, key=lambda g: -copies[g] * funcs[g]["own"])
    for g in rows[:top]:
        print(f"  {copies[g] * funcs[g]['own']:>12,} {copies[g]:>8,} x {funcs[g]['own']:>5}  {nm(g)}")
    print("\nfunctions that panic directly:")
    for g in sorted(funcs, key=nm):
        if funcs[g]["aborts"]:
            print("  " + nm(g))


if __name__ == "__main__":
    main()
