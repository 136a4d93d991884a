#!/usr/bin/env python3
"""Compile-test variants of a module for a driver crash hunt (BENCHMARKS.md
"GPU", session 22); the results are wrong code, only the compile matters:
noi8 turns every 8-bit integer type into the 32-bit one of the same
signedness (and drops the Int8 capability; same-width conversions become
OpCopyObject or OpBitcast), nocopy turns OpCopyMemory into OpLoad and
OpStore.

usage: knock_out.py in.spvasm out.spvasm noi8,nocopy"""
import re, sys
lines = open(sys.argv[1]).read().split('\n')
what = sys.argv[3].split(',')
maxid = max(int(x) for l in lines for x in re.findall(r'%(\d+)', l))
nid = [maxid + 1]
def fresh():
    nid[0] += 1
    return '%%%d' % (nid[0] - 1)
types = {}
ptr_pointee = {}
for l in lines:
    m = re.match(r'\s*(%\d+) = OpTypeInt (\d+) ([01])', l)
    if m: types[m.group(1)] = (int(m.group(2)), m.group(3))
    m = re.match(r'\s*(%\d+) = OpTypePointer \w+ (%\d+)', l)
    if m: ptr_pointee[m.group(1)] = m.group(2)
valtype = {}
for l in lines:
    m = re.match(r'\s*(%\d+) = Op\w+ (%\d+)', l)
    if m: valtype[m.group(1)] = m.group(2)
out = []
if 'noi8' in what:
    i32 = {s: t for t, (w, s) in types.items() if w == 32}
    rep = {t: i32[s] for t, (w, s) in types.items() if w == 8}
    sub = lambda l: re.sub(r'%\d+', lambda m: rep.get(m.group(0), m.group(0)), l)
    # values that become 32-bit
    for l in lines:
        if re.match(r'\s*%\d+ = OpTypeInt 8', l) or l.strip() == 'OpCapability Int8':
            continue
        m = re.match(r'\s*(%\d+) = Op([SU]Convert) (%\d+) (%\d+)', l)
        if m:
            rt = rep.get(m.group(3), m.group(3)); st = rep.get(valtype.get(m.group(4)), valtype.get(m.group(4)))
            if types.get(rt, (0,))[0] == 32 and types.get(st, (0,))[0] == 32:
                op = 'OpCopyObject' if rt == st else 'OpBitcast'
                out.append('%s = %s %s %s' % (m.group(1), op, rt, m.group(4)))
                continue
        out.append(sub(l))
    lines = out; out = []
if 'nocopy' in what:
    for l in lines:
        m = re.match(r'\s*OpCopyMemory (%\d+) (%\d+)\s*$', l)
        if m:
            T = ptr_pointee[valtype[m.group(2)]]
            t = fresh()
            out.append('%s = OpLoad %s %s' % (t, T, m.group(2)))
            out.append('OpStore %s %s' % (m.group(1), t))
            continue
        out.append(l)
    lines = out
open(sys.argv[2], 'w').write('\n'.join(lines))
