#!/usr/bin/env python3
"""Box-ness of grime's rain stains (BENCHMARKS.md, twenty-seventh pass,
helper boxes29): how much the stains under ledges read as hard-edged
boxes.

usage: boxness.py GRIME OUTDIR PHOTO...

Runs `GRIME run PHOTO --years 50 --seed 100 --layers-dir` and `GRIME
scene` per photo (kept in OUTDIR, reused if there; a wrapper script as
GRIME can add `--set` overrides to `run`), composites the photo and its
40 rain layers (normal blend at their opacity; not the washed runs, moss
or dust) and takes the darkening D = luma(photo) - luma(rain), >= 0.

Per photo: meanD (mean D over the wall region); seams: of the boundary of
the stain mask D > t (t = 4, 8, 16, averaged), the share lying in straight
runs of at least 12 px: `bot` (stain above, clean below: stains stopping
on a line), `top` (clean above, stain below: stains starting on a line),
`side` (vertical edges). Per ledge of the scene at least 40 px wide: the
column means of D in a band 6% of the photo high under it (wall pixels
only); `CV` their coefficient of variation along the ledge (how uneven,
higher = less of a box) and `end/mid` the mean of its outer tenths over
its middle (above 1: darkest at the ends, cut there).
"""
import sys, os, json, subprocess
import numpy as np
from PIL import Image
grime, out = sys.argv[1], sys.argv[2]
photos = sys.argv[3:]
N = 12  # a seam: a straight run of at least N px
def luma(a): return a[...,0]*0.299+a[...,1]*0.587+a[...,2]*0.114
def runs_share(edge, N):
    # edge: bool 2D, runs along axis 1; share of True in runs >= N
    tot = edge.sum(); 
    if tot == 0: return 0.0, 0
    long = 0
    for row in edge:
        if not row.any(): continue
        d = np.diff(np.concatenate([[0], row.astype(np.int8), [0]]))
        s = np.where(d == 1)[0]; e = np.where(d == -1)[0]
        L = e - s; long += L[L >= N].sum()
    return long / tot, tot
rows = []
allcv = []; allend = []
for p in photos:
    name = os.path.basename(p).rsplit('.',1)[0]
    L = os.path.join(out, 'L_' + name)
    if not os.path.exists(os.path.join(L, 'manifest.json')):
        subprocess.run([grime, 'run', p, '-o', os.path.join(out, name + '.png'), '--years', '50', '--seed', '100', '--layers-dir', L], check=True, capture_output=True)
    if not os.path.exists(os.path.join(out, name + '.json')):
        subprocess.run([grime, 'scene', p, '-o', os.path.join(out, name + '.json')], check=True, capture_output=True)
    m = json.load(open(os.path.join(L, 'manifest.json')))
    photo = np.array(Image.open(os.path.join(L, '00-photo.png')).convert('RGB')).astype(np.float64)
    img = photo.copy()
    for l in m['layers']:
        if not l['name'].startswith('rain') or l['name'] == 'rain washed': continue
        a = np.array(Image.open(os.path.join(L, l['file']))).astype(np.float64) / 255
        al = a[...,3:4] * l['opacity']
        img = img * (1 - al) + a[...,:3] * 255 * al
    D = np.clip(luma(photo) - luma(img), 0, None)
    wall = np.array(Image.open(os.path.join(L, 'region.png')).convert('L')) > 128
    H, W = D.shape
    meanD = D[wall].mean() if wall.any() else 0
    # seams
    res = {}
    for t in (4.0, 8.0, 16.0):
        M = D > t
        bot = M[:-1] & ~M[1:]   # stain above, clean below: horizontal bottom edges
        top = ~M[:-1] & M[1:]
        side = (M[:, :-1] != M[:, 1:]).T  # vertical edges, runs along y
        res[t] = (runs_share(bot, N), runs_share(top, N), runs_share(side, N))
    bot_share = np.mean([res[t][0][0] for t in res]); top_share = np.mean([res[t][1][0] for t in res]); side_share = np.mean([res[t][2][0] for t in res])
    # per ledge evenness
    sc = json.load(open(os.path.join(out, name + '.json')))
    band = max(8, int(0.06 * H))
    cvs = []; ends = []
    for led in sc['ledges']:
        pl = np.array(led['polyline'])
        x0, x1 = int(np.ceil(pl[0,0])), int(np.floor(pl[-1,0]))
        if x1 - x0 < 40: continue
        cm = []
        for x in range(x0, x1 + 1):
            y = np.interp(x, pl[:,0], pl[:,1])
            ya, yb = int(y) + 2, min(H, int(y) + 2 + band)
            w = wall[ya:yb, x]
            if w.sum() < band // 2: cm.append(np.nan); continue
            cm.append(D[ya:yb, x][w].mean())
        cm = np.array(cm)
        ok = ~np.isnan(cm)
        if ok.sum() < 30 or np.nanmean(cm) < 1.0: continue
        cvs.append(np.nanstd(cm) / np.nanmean(cm))
        n = len(cm); k = max(3, n // 10)
        e = np.nanmean(np.concatenate([cm[:k], cm[-k:]])); mid = np.nanmean(cm[k:-k])
        ends.append(e / max(mid, 1e-6))
    allcv += cvs; allend += ends
    rows.append((name[-28:], meanD, bot_share, top_share, side_share, np.mean(cvs) if cvs else np.nan, np.mean(ends) if ends else np.nan, len(cvs)))
    print('%-28s meanD %5.2f seams bot %.3f top %.3f side %.3f  ledgeCV %.3f end/mid %.3f (%d)' % rows[-1], flush=True)
r = np.array([x[1:] for x in rows], dtype=float)
print('MEAN  meanD %.2f seams bot %.3f top %.3f side %.3f | ledges %d: CV mean %.3f median %.3f, end/mid mean %.3f median %.3f' % (r[:,0].mean(), r[:,1].mean(), r[:,2].mean(), r[:,3].mean(), len(allcv), np.mean(allcv), np.median(allcv), np.mean(allend), np.median(allend)))
