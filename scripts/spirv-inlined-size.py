#!/usr/bin/env python3
"""The size of a SPIR-V module's entry points once every call is inlined.

Mesa's Vulkan drivers (lavapipe included) inline every function call of a
shader before compiling it, so a function called from k places costs k
copies: what lavapipe's compile time and memory grow with (BENCHMARKS.md
"GPU", session 36). This reads a module (as `scripts/build-spirv.sh`
writes it), counts the instructions of each function and its calls, and
prints each entry point's inlined size, then the functions whose copies
weigh most (copies x inlined size).

(`scripts/spirv-inline-report.py` is the other side: from a module dumped
*before* rust-gpu's linker inlines, it predicts what that linker inlines.
This one reads the linked module a driver receives.)

Usage: scripts/spirv-inlined-size.py MODULE.spv [ROWS]
"""
import collections
import struct
import sys

OP_NAME, OP_ENTRY_POINT = 5, 15
OP_FUNCTION, OP_FUNCTION_END, OP_FUNCTION_CALL = 54, 56, 57


def string(words):
    raw = b"".join(struct.pack("<I", w) for w in words)
    return raw.split(b"\0")[0].decode("utf8", "replace")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    data = open(sys.argv[1], "rb").read()
    rows = int(sys.argv[2]) if len(sys.argv) > 2 else 25
    words = struct.unpack("<%dI" % (len(data) // 4), data)
    if not words or words[0] != 0x07230203:
        sys.exit("%s: not a SPIR-V module" % sys.argv[1])
    names, entries = {}, []
    funcs = {}  # id -> [own instruction count, Counter of callees]
    current = None
    i = 5
    while i < len(words):
        count, op = words[i] >> 16, words[i] & 0xFFFF
        if count == 0:
            sys.exit("malformed instruction at word %d" % i)
        ops = words[i + 1 : i + count]
        if op == OP_NAME:
            names[ops[0]] = string(ops[1:])
        elif op == OP_ENTRY_POINT:
            entries.append((ops[1], string(ops[2:])))
        elif op == OP_FUNCTION:
            current = ops[1]
            funcs[current] = [0, collections.Counter()]
        elif op == OP_FUNCTION_END:
            current = None
        elif current is not None:
            funcs[current][0] += 1
            if op == OP_FUNCTION_CALL:
                funcs[current][1][ops[2]] += 1
        i += count

    # Callees before callers (the call graph is acyclic: no recursion).
    order, seen = [], set()
    for root in funcs:
        if root in seen:
            continue
        seen.add(root)
        stack = [(root, iter(funcs[root][1]))]
        while stack:
            f, callees = stack[-1]
            g = next(callees, None)
            if g is None:
                order.append(f)
                stack.pop()
            elif g not in seen:
                seen.add(g)
                stack.append((g, iter(funcs[g][1])))
    inlined = {}
    for f in order:
        own, calls = funcs[f]
        inlined[f] = own + sum(c * inlined[g] for g, c in calls.items())
    # Copies of each function in the entry points, inlined.
    copies = collections.Counter()
    for f, _ in entries:
        copies[f] += 1
    for f in reversed(order):
        for g, c in funcs[f][1].items():
            copies[g] += copies[f] * c

    def name(f):
        return names.get(f, "%%%d" % f)

    print("%d functions, %d instructions" % (len(funcs), sum(v[0] for v in funcs.values())))
    for f, entry in entries:
        print("entry point %s: %d instructions inlined" % (entry, inlined[f]))
    heavy = sorted(
        ((copies[f] * inlined[f], copies[f], inlined[f], name(f)) for f in funcs if copies[f]),
        reverse=True,
    )
    print("\n%12s %7s %10s  function" % ("copies*size", "copies", "size"))
    for weight, n, size, fname in heavy[:rows]:
        print("%12d %7d %10d  %s" % (weight, n, size, fname[:150]))


if __name__ == "__main__":
    main()
