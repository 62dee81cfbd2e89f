"""The pictures of docs/constraints.md: top views (looking down z) of run folders' answers,
side by side. Needs Pillow (pip install pillow).

usage: constraint_pictures.py OUT.png 'DIR|TITLE|MARK' ...

TITLE lines are separated by a literal \n. MARK: empty; 'x,y,r': the disc of radius r (the
largest gap) about (x, y); 'dev': the vertex of the answer that moves most at equilibrium;
'pairs': kept curves coloured by pair (curves 2k, 2k+1); 'rest': kept curves drawn at rest
(else at equilibrium, from answer.obj). Removed curves are drawn thin, at iteration 0's state.
"""
import sys, json, os
from PIL import Image, ImageDraw, ImageFont

def polylines(path):
    vs, ls = [], []
    for line in open(path):
        t = line.split()
        if not t: continue
        if t[0] == 'v': vs.append(tuple(map(float, t[1:4])))
        elif t[0] == 'l': ls.append([vs[int(i) - 1] for i in t[1:]])
    return vs, ls

def mesh(path):
    vs, fs = [], []
    for line in open(path):
        t = line.split()
        if not t: continue
        if t[0] == 'v': vs.append(tuple(map(float, t[1:4])))
        elif t[0] == 'f': fs.append([int(x.split('/')[0]) - 1 for x in t[1:4]])
    return vs, fs

S = 440
try:
    font = ImageFont.truetype('/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf', 15)
except Exception:
    font = ImageFont.load_default()

def panel(d, title, gap):
    mv, mf = mesh(os.path.join(d, 'mesh.obj'))
    xs = [v[0] for v in mv]; ys = [v[1] for v in mv]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    ext = max(x1 - x0, y1 - y0)
    pad, top = 12, 46
    sc = (S - 2 * pad) / ext
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    P = lambda p: (S / 2 + (p[0] - cx) * sc, top + (S - 2 * pad) / 2 + pad - (p[1] - cy) * sc)
    im = Image.new('RGB', (S, S + top), (255, 255, 255))
    dr = ImageDraw.Draw(im)
    for f in mf:
        dr.polygon([P(mv[i]) for i in f], fill=(226, 222, 212))
    r = json.load(open(os.path.join(d, 'result.json')))
    a = r['answer']
    _, allc = polylines(os.path.join(d, 'iterations', '0000.obj'))
    for i, c in enumerate(allc):
        if a is None or i not in a['curves']:
            dr.line([P(p) for p in c], fill=(225, 120, 100), width=1)
    if gap and gap not in ('dev', 'pairs', 'rest'):
        gx, gy, gr = map(float, gap.split(','))
        q = P((gx, gy)); rr = gr * sc
        dr.ellipse([q[0] - rr, q[1] - rr, q[0] + rr, q[1] + rr], outline=(200, 40, 160), width=2)
        dr.ellipse([q[0] - 4, q[1] - 4, q[0] + 4, q[1] + 4], fill=(200, 40, 160))
    if a is not None:
        _, kept = polylines(os.path.join(d, 'answer.obj'))
        if gap == 'rest':
            net = json.load(open(os.path.join(d, 'network.json')))
            kept = [[net['positions'][v] for v in net['rods'][c]['vertices']] for c in a['curves']]
        pal = [(25, 80, 170), (20, 150, 60), (230, 130, 0), (140, 40, 180), (0, 150, 170), (180, 30, 30),
               (90, 90, 90), (200, 170, 0), (30, 30, 120), (120, 70, 20), (0, 100, 60), (220, 60, 130)]
        for i, c in enumerate(kept):
            col = pal[(a['curves'][i] // 2) % len(pal)] if gap == 'pairs' else (25, 80, 170)
            dr.line([P(p) for p in c], fill=col, width=3)
    if gap == 'dev' and a is not None:
        import struct
        net = json.load(open(os.path.join(d, 'network.json')))
        raw = open(os.path.join(d, 'states', 'answer.bin'), 'rb').read()
        u = struct.unpack('<%dd' % (len(raw) // 8), raw)
        best, at = -1.0, None
        for c in a['curves']:
            for v in net['rods'][c]['vertices']:
                m = (u[3*v]**2 + u[3*v+1]**2 + u[3*v+2]**2) ** 0.5
                if m > best: best, at = m, net['positions'][v]
        q = P(at)
        dr.ellipse([q[0] - 14, q[1] - 14, q[0] + 14, q[1] + 14], outline=(200, 40, 160), width=3)
        tx = q[0] + 16 if q[0] < S - 150 else q[0] - 150
        dr.text((tx, q[1] + 14), 'largest move %.2f' % best, fill=(150, 20, 120), font=font)
    lines = title.split('\\n')
    for k, t in enumerate(lines):
        dr.text((8, 4 + 19 * k), t, fill=(20, 20, 20), font=font)
    return im

out = sys.argv[1]
panels = []
for spec in sys.argv[2:]:
    d, title, gap = (spec.split('|') + ['', ''])[:3]
    panels.append(panel(d, title, gap))
W = sum(p.size[0] for p in panels) + 10 * (len(panels) - 1)
H = max(p.size[1] for p in panels)
canvas = Image.new('RGB', (W, H), (255, 255, 255))
x = 0
for p in panels:
    canvas.paste(p, (x, 0)); x += p.size[0] + 10
canvas = canvas.quantize(colors=64, method=Image.MEDIANCUT, dither=Image.NONE)
canvas.save(out, optimize=True)
print(out, os.path.getsize(out))
