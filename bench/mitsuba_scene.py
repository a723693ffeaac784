"""Render a scene exported by `cargo run --release --example export_mitsuba -- SCENE.pbrt DIR`
with Mitsuba 3 (see ../shared/peers/README.md for the install), so an independent renderer
renders exactly the description mcrender's loader produced.

Usage: python bench/mitsuba_scene.py DIR OUT.exr [--res WxH] [--spp N] [--max-depth D]
       [--distribution ggx|beckmann] [--conductor-scale S] [--variant llvm_ad_rgb]
Prints one JSON line with the wall time and the image's mean RGB.
"""
import argparse, glob, json, os, time

for lib in sorted(glob.glob('/usr/lib/x86_64-linux-gnu/libLLVM*.so.1*')):
    if any(v in lib for v in ('17', '18', '19', '20')):
        os.environ.setdefault('DRJIT_LIBLLVM_PATH', lib)
import numpy as np
import mitsuba as mi
import drjit as dr

p = argparse.ArgumentParser()
p.add_argument('dir'); p.add_argument('out')
p.add_argument('--res', default=None); p.add_argument('--spp', type=int, default=64)
p.add_argument('--max-depth', type=int, default=None); p.add_argument('--distribution', default='ggx')
p.add_argument('--conductor-scale', type=float, default=1.0)
p.add_argument('--variant', default='llvm_ad_rgb'); p.add_argument('--threads', type=int, default=2)
a = p.parse_args()
mi.set_variant(a.variant)
dr.set_thread_count(a.threads)
S = json.load(open(os.path.join(a.dir, 'scene.json')))
w, h = (map(int, a.res.split('x')) if a.res else (S['width'], S['height']))
# Column-major 4x4 -> rows; Mitsuba's camera x axis points left where pbrt's points right.
m = np.array(S['world_from_camera'], dtype=float).reshape(4, 4).T @ np.diag([-1.0, 1, 1, 1])
rgb = lambda v: {'type': 'rgb', 'value': v}
scene = {'type': 'scene',
         'integrator': {'type': 'path', 'max_depth': a.max_depth if a.max_depth is not None else S['max_depth'] + 1},
         'sensor': {'type': 'perspective', 'fov': S['fov'], 'fov_axis': 'smaller', 'to_world': mi.ScalarTransform4f(m.tolist()),
                    'film': {'type': 'hdrfilm', 'width': w, 'height': h, 'rfilter': {'type': 'tent'}},
                    'sampler': {'type': 'independent', 'sample_count': a.spp}}}
def bsdf(mat):
    if mat['type'] == 'diffuse':
        b = {'type': 'diffuse', 'reflectance': rgb(mat['reflectance'])}
    else:
        b = {'type': 'roughconductor', 'distribution': a.distribution, 'alpha_u': mat['alpha_u'], 'alpha_v': mat['alpha_v'],
             'eta': rgb(mat['eta']), 'k': rgb(mat['k'])}
        if a.conductor_scale != 1.0:  # a grey factor on the reflectance, for testing hypotheses
            b['specular_reflectance'] = {'type': 'rgb', 'value': [a.conductor_scale] * 3}
    return {'type': 'twosided', 'bsdf': b}  # pbrt's surfaces reflect on both sides
for i, s in enumerate(S['shapes']):
    if s['kind'] == 'mesh':
        sh = {'type': 'obj', 'filename': s['file'], 'face_normals': True, 'bsdf': bsdf(s['material'])}
    else:
        sh = {'type': 'sphere', 'center': s['center'], 'radius': s['radius'], 'bsdf': bsdf(s['material'])}
    if s['emitter'] is not None:
        sh['emitter'] = {'type': 'area', 'radiance': rgb(s['emitter']['radiance'])}
    scene[f'shape{i}'] = sh
sc = mi.load_dict(scene)
t0 = time.perf_counter()
img = np.array(mi.render(sc, spp=a.spp))
wall = time.perf_counter() - t0
mi.Bitmap(img.astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).write(a.out)
print(json.dumps(dict(variant=a.variant, distribution=a.distribution, spp=a.spp, res=[w, h], wall_s=round(wall, 3),
                      mean_rgb=[round(float(x), 6) for x in img.reshape(-1, 3).mean(0)])))
