#!/usr/bin/env python3
"""Splits every OpPhi whose type is a struct holding pointers (rust-gpu's form
of a Rust struct of slices or references) into one OpPhi per member, with
OpCompositeExtract at the end of each predecessor and OpCompositeConstruct
after the block's phis, until none is left. Nested structs take one round
each. A compile-crash experiment for NVIDIA's driver (BENCHMARKS.md "GPU",
session 22); the output needs pointer_phi.py before it validates.

usage: phi_split.py in.spvasm out.spvasm   (spirv-dis --raw-id text)"""
import re, sys
lines = open(sys.argv[1]).read().split('\n')
ptr, structs = set(), {}
maxid = 0
for l in lines:
    for x in re.findall(r'%(\d+)', l):
        maxid = max(maxid, int(x))
    m = re.match(r'\s*(%\d+) = OpTypePointer', l)
    if m: ptr.add(m.group(1))
    m = re.match(r'\s*(%\d+) = OpTypeStruct (.*)', l)
    if m: structs[m.group(1)] = m.group(2).split()
hp = set(); ch = True
while ch:
    ch = False
    for s, mem in structs.items():
        if s not in hp and any(x in ptr or x in hp for x in mem):
            hp.add(s); ch = True
nid = maxid + 1
def fresh():
    global nid
    nid += 1
    return '%%%d' % (nid - 1)
total = 0
for it in range(10):
    # index blocks: label id -> line index of label; find insertion point per block
    label_at = {}
    for i, l in enumerate(lines):
        m = re.match(r'\s*(%\d+) = OpLabel', l)
        if m: label_at[m.group(1)] = i
    def insert_point(b):
        i = label_at[b] + 1
        while True:
            op = lines[i].split('=')[-1].split()[0] if '=' in lines[i] else lines[i].split()[0]
            if op in ('OpBranch', 'OpBranchConditional', 'OpSwitch', 'OpReturn', 'OpReturnValue', 'OpUnreachable', 'OpKill'):
                j = i
                if j > 0 and lines[j-1].split()[0] in ('OpSelectionMerge', 'OpLoopMerge'):
                    j -= 1
                return j
            i += 1
    inserts = {}   # line index -> list of lines to insert before it
    replace = {}   # line index -> list of lines
    after_phis = {}
    n = 0
    for i, l in enumerate(lines):
        m = re.match(r'\s*(%\d+) = OpPhi (%\d+) (.*)', l)
        if not m or m.group(2) not in hp: continue
        r, S, rest = m.groups()
        pairs = rest.split()
        pairs = list(zip(pairs[0::2], pairs[1::2]))
        mem = structs[S]
        newphis = []
        parts = []
        for j, T in enumerate(mem):
            pj = fresh(); parts.append(pj)
            ops = []
            for v, b in pairs:
                e = fresh()
                inserts.setdefault(insert_point(b), []).append('%s = OpCompositeExtract %s %s %d' % (e, T, v, j))
                ops += [e, b]
            newphis.append('%s = OpPhi %s %s' % (pj, T, ' '.join(ops)))
        replace[i] = newphis
        # find the block's first non-phi line
        k = i + 1
        while re.match(r'\s*%\d+ = OpPhi', lines[k]) or lines[k].strip().startswith('OpLine') or lines[k].strip().startswith('OpNoLine'):
            k += 1
        after_phis.setdefault(k, []).append('%s = OpCompositeConstruct %s %s' % (r, S, ' '.join(parts)))
        n += 1
    if n == 0: break
    total += n
    out = []
    for i, l in enumerate(lines):
        out += after_phis.get(i, [])
        out += inserts.get(i, [])
        out += replace.get(i, [l])
    lines = out
    print('iteration', it, 'phis split:', n, file=sys.stderr)
open(sys.argv[2], 'w').write('\n'.join(lines))
print('total', total, file=sys.stderr)
