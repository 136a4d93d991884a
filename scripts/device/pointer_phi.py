#!/usr/bin/env python3
"""After phi_split.py: replaces each OpPhi of pointer type whose incoming
values all come from one access chain into a global variable with constant
indices (after looking through extracts, inserts, constructs and phis) by
that access chain, recomputed after the block's phis; one that resolves to
a global variable or a value of the function's first block is replaced by
it. Without VariablePointers, Vulkan allows no pointer phis. Prints how
many were replaced and how many are left (BENCHMARKS.md "GPU", session 22).

usage: pointer_phi.py in.spvasm out.spvasm"""
import re, sys, collections
lines = open(sys.argv[1]).read().split('\n')
ptr = set(); defs = {}; first_block = set()
cur_fn = None; blk = 0
first_fn_line = 10**9
for i, l in enumerate(lines):
    m = re.match(r'\s*(%\d+) = OpTypePointer', l)
    if m: ptr.add(m.group(1))
    m = re.match(r'\s*(%\d+) = (Op\w+)(.*)', l)
    if m:
        defs[m.group(1)] = (m.group(2), m.group(3).split(), i)
        if m.group(2) == 'OpFunction': cur_fn = m.group(1); blk = 0; first_fn_line = min(first_fn_line, i)
        elif m.group(2) == 'OpLabel': blk += 1
        elif cur_fn and blk <= 1: first_block.add(m.group(1))
    if l.strip() == 'OpFunctionEnd': cur_fn = None
def member(s, path, seen):
    op, a, _ = defs.get(s, (None, [], 0))
    if op == 'OpCompositeConstruct':
        return resolve(a[1 + path[0]], seen) if len(path) == 1 else member(a[1 + path[0]], path[1:], seen)
    if op == 'OpCompositeInsert':
        ipath = [int(x) for x in a[3:]]
        if ipath == path: return resolve(a[1], seen)
        if ipath[:len(path)] == path: return {('?', s)}
        if path[:len(ipath)] == ipath: return member(a[1], path[len(ipath):], seen)
        return member(a[2], path, seen)
    if op == 'OpUndef': return set()
    if op == 'OpCompositeExtract':
        return member(a[1], [int(x) for x in a[2:]] + path, seen)
    if op == 'OpPhi':
        if s in seen: return set()
        seen = seen | {s}
        r = set()
        for v in a[1::2]: r |= member(v, path, seen)
        return r
    return {('?', s, op)}
def resolve(v, seen):
    op, a, _ = defs.get(v, ('global?', [], 0))
    if op == 'OpCompositeExtract':
        return member(a[1], [int(x) for x in a[2:]], seen)
    if op == 'OpPhi' and a[0] in ptr:
        if v in seen: return set()
        seen = seen | {v}
        r = set()
        for x in a[1::2]: r |= resolve(x, seen)
        return r
    if op == 'OpUndef': return set()
    return {v}
sys.setrecursionlimit(100000)
# global variables and constants: declared before the first function
module_level = {k for k, d in defs.items() if d[0] in ('OpVariable', 'OpConstant', 'OpConstantComposite', 'OpConstantNull', 'OpConstantTrue', 'OpConstantFalse') and d[2] < first_fn_line}
remat = {}
rep = {}; bad = collections.Counter()
for v, (op, a, i) in defs.items():
    if op == 'OpPhi' and a[0] in ptr:
        r = resolve(v, frozenset())
        ok = len(r) == 1 and isinstance(next(iter(r)), str)
        if ok:
            root = next(iter(r))
            rop = defs.get(root, ('?',))[0]
            if rop == 'OpVariable' or root in first_block:
                rep[v] = root; continue
            if rop in ('OpAccessChain', 'OpInBoundsAccessChain'):
                ra = defs[root][1]
                if all(x in module_level for x in ra[1:]):
                    remat[v] = '%s = %s %s' % (v, rop, ' '.join(ra)); continue
            bad['root not dominating: ' + rop] += 1
        else:
            bad['roots: %d' % len(r)] += 1
            if bad['roots: %d' % len(r)] < 3: print(v, r, file=sys.stderr)
print('pointer phis rematerialized:', len(remat), 'replaced:', len(rep), 'left:', dict(bad), file=sys.stderr)
out = []; pending = []
for l in lines:
    m = re.match(r'\s*(%\d+) = OpPhi', l)
    if m and m.group(1) in rep: continue
    if m and m.group(1) in remat:
        pending.append(remat[m.group(1)]); continue
    if pending and not re.match(r'\s*%\d+ = OpPhi', l) and not l.strip().startswith('OpLine'):
        out += pending; pending.clear()
    out.append(re.sub(r'%\d+', lambda mm: rep.get(mm.group(0), mm.group(0)), l) if '%' in l else l)
open(sys.argv[2], 'w').write('\n'.join(out))
