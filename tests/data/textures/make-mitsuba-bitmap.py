# Writes the two test images and mitsuba-bitmap.csv: Mitsuba 3 bitmap lookups of them at OBJ
# uvs, for tests/texture_mitsuba.rs. Run with the Python that has mitsuba:
#   python tests/data/textures/make-mitsuba-bitmap.py "$PWD/tests/data/textures"
import mitsuba as mi, numpy as np, sys
mi.set_variant('scalar_rgb')
out = sys.argv[1]
rng = np.random.default_rng(7)
img = rng.integers(0, 256, size=(3, 5, 3), dtype=np.uint8)  # height 3, width 5
mi.Bitmap(img, pixel_format=mi.Bitmap.PixelFormat.RGB).write(out + '/noise-5x3.png')
grey = rng.integers(0, 256, size=(4, 2), dtype=np.uint8)
mi.Bitmap(grey, pixel_format=mi.Bitmap.PixelFormat.Y).write(out + '/grey-2x4.png')
rows = []
for name, raw in [('noise-5x3.png', False), ('noise-5x3.png', True), ('grey-2x4.png', True)]:
    tex = mi.load_dict({'type': 'bitmap', 'filename': out + '/' + name, 'raw': raw})
    for k in range(64):
        u, v = rng.uniform(-2.5, 2.5, 2)
        if k % 4 == 0:
            u, v = np.round(u * 10) / 10, np.round(v * 6) / 6
        si = mi.SurfaceInteraction3f()
        # The OBJ's (u, v) as Mitsuba's OBJ loader stores it: (u, 1 - v).
        si.uv = mi.Point2f(float(u), float(1 - v))
        if name.startswith('grey'):
            c = [tex.eval_1(si)] * 3
        else:
            c = tex.eval(si)
        rows.append(f"{name},{int(raw)},{float(u)!r},{float(v)!r},{c[0]!r},{c[1]!r},{c[2]!r}")
open(out + '/mitsuba-bitmap.csv', 'w').write("file,raw,u,v,r,g,b\n" + "\n".join(rows) + "\n")
print(len(rows), mi.__version__)
