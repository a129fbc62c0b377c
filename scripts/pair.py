#!/usr/bin/env python3
"""Blind pairwise check (docs/blind-review.md): each photo aged by two grime
binaries, the sides at random, for a critic who has not seen the work.

usage: pair.py LIST OLD NEW OUT TAG [--years 50] [--seed 100] [--shuffle S]
               [--old-set k=v ...] [--new-set k=v ...] [--keys DIR]

LIST: a file of photo paths. OLD, NEW: absolute paths to two grime binaries
(e.g. main's and a branch's build). OUT gets pairNN_A.jpg and pairNN_B.jpg
and nothing that tells the sides; the key (which side is NEW, per photo)
goes to KEYS/TAG.json, outside OUT (default: OUT's parent folder).
`--print-prompt` prints the critic's brief for OUT instead.

The critic's brief (give it as the whole prompt, with FOLDER and N filled):

You are an experienced photo retoucher and architectural photographer asked to judge image realism. Work only by looking at images; do not read or run anything else on this machine except what is named here.

In the folder FOLDER there are N pairs of images, named pairNN_A.jpg and pairNN_B.jpg. In each pair both images start from the same real street photo of a building, and in both a program has added weathering (rain streaks, dirt, stains, perhaps moss) to make the building look older. The two versions of a pair differ in how that weathering was made.

For each pair, decide which version looks more like a real, unretouched photo of a genuinely old, weathered building — the one a retoucher would be less likely to catch as edited — or say "equal" if you cannot honestly tell them apart. Look closely: open each image, and zoom into regions (you can view the images with the file viewing tool; if it helps, you may crop regions with Python/PIL into /tmp and view those crops) to compare the same area in A and B. Differences may be subtle.

Report, for every pair:
- pair NN: A / B / equal, your confidence (50-100%), and in one or two sentences the concrete visual reason (where in the image, what you saw).

Then list the flaws both versions share, strongest first (what still gives the weathering away as fake), and anything that looks right.

Be honest and specific; "equal" is a valid answer when you see no real difference.
"""
import argparse, json, os, random, subprocess, sys, tempfile
from PIL import Image

PROMPT = __doc__.split('(give it as the whole prompt, with FOLDER and N filled):\n\n', 1)[1]

ap = argparse.ArgumentParser()
ap.add_argument('list'); ap.add_argument('old'); ap.add_argument('new')
ap.add_argument('out'); ap.add_argument('tag')
ap.add_argument('--years', default='50'); ap.add_argument('--seed', default='100')
ap.add_argument('--shuffle', type=int, default=1)
ap.add_argument('--old-set', action='append', default=[])
ap.add_argument('--new-set', action='append', default=[])
ap.add_argument('--keys', default=None)
ap.add_argument('--print-prompt', action='store_true')
a = ap.parse_args()
if a.print_prompt:
    n = len([l for l in open(a.list) if l.strip()])
    print(PROMPT.replace('FOLDER', os.path.abspath(a.out)).replace('N pairs', f'{n} pairs'))
    sys.exit(0)
keys = a.keys or os.path.dirname(os.path.abspath(a.out))
photos = [l.strip() for l in open(a.list) if l.strip()]
os.makedirs(a.out, exist_ok=True)
rng = random.Random(a.shuffle)
key = {'old': a.old, 'new': a.new, 'old_set': a.old_set, 'new_set': a.new_set,
       'years': a.years, 'pairs': {}}
tmp = tempfile.mkdtemp(prefix='pair_')


def age(binary, sets, photo, out):
    cmd = [binary, 'run', photo, '-o', out, '--years', a.years, '--seed', a.seed]
    for s in sets:
        cmd += ['--set', s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f'{binary} failed on {photo}: {r.stderr.strip()}')


for i, p in enumerate(photos, 1):
    o = os.path.join(tmp, f'{i}_old.png'); n = os.path.join(tmp, f'{i}_new.png')
    age(a.old, a.old_set, p, o)
    age(a.new, a.new_set, p, n)
    new_is_a = rng.random() < 0.5
    sides = {'A': n if new_is_a else o, 'B': o if new_is_a else n}
    for s, f in sides.items():
        Image.open(f).convert('RGB').save(os.path.join(a.out, f'pair{i:02d}_{s}.jpg'), quality=95)
    key['pairs'][f'{i:02d}'] = {'photo': os.path.basename(p), 'new': 'A' if new_is_a else 'B'}
    print(f'pair {i:02d} {os.path.basename(p)}', flush=True)
json.dump(key, open(os.path.join(keys, f'{a.tag}.json'), 'w'), indent=1)
print('key', os.path.join(keys, f'{a.tag}.json'))
