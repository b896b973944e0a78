#!/usr/bin/env python3
"""Seed corpora for the fuzz harnesses of tests/fuzz, generated from the real assets in
../shared/data (never committed: they are rebuilt whenever they are needed).

Usage: scripts/fuzz_seeds.py OUT_DIR [DERMIS_BINARY]

Writes OUT_DIR/<harness>/ for obj, ply, dsurf, capi, asset_stream, gltf and assimp. The .dsurf
seeds (fitted files, their runtime archives, and the asset streams cut from them) need the
dermis tool (a Release build); without it those harnesses start from the regression inputs
only. Prints what it wrote; exits 0 with a
note when ../shared/data is absent.
"""
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, '..', 'shared', 'data')


def read_obj(path, max_vertices=None):
    vs, fs = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == 'v':
                vs.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == 'f':
                fs.append([int(x.split('/')[0]) - 1 for x in t[1:]])
    if max_vertices is not None:
        fs = [f for f in fs if max(f) < max_vertices]
        vs = vs[:max_vertices]
    return vs, fs


def obj_text(vs, fs):
    return ''.join('v %.6g %.6g %.6g\n' % v for v in vs) + \
        ''.join('f ' + ' '.join(str(i + 1) for i in f) + '\n' for f in fs)


def ply_bytes(vs, fs, fmt):
    head = 'ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\n' \
           'property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n' \
           % (fmt, len(vs), len(fs))
    if fmt == 'ascii':
        body = ''.join('%.6g %.6g %.6g\n' % v for v in vs) + \
            ''.join('%d %s\n' % (len(f), ' '.join(map(str, f))) for f in fs)
        return (head + body).encode()
    e = '<' if fmt == 'binary_little_endian' else '>'
    out = bytearray(head.encode())
    for v in vs:
        out += struct.pack(e + 'fff', *v)
    for f in fs:
        out += struct.pack(e + 'B', len(f)) + struct.pack(e + '%di' % len(f), *f)
    return bytes(out)


def collada(vs, fs, depth):
    pos = ' '.join('%.5g' % c for v in vs for c in v)
    idx = ' '.join(str(i) for f in fs for i in f[:3])
    nodes_open = ''.join('<node id="n%d">' % k for k in range(depth))
    nodes_close = '</node>' * depth
    return ('<?xml version="1.0"?>\n<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" '
            'version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset><library_geometries>'
            '<geometry id="g"><mesh><source id="p"><float_array id="pa" count="%d">%s</float_array>'
            '<technique_common><accessor source="#pa" count="%d" stride="3"><param name="X" type="float"/>'
            '<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>'
            '</source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices>'
            '<triangles count="%d"><input semantic="VERTEX" source="#v" offset="0"/><p>%s</p></triangles>'
            '</mesh></geometry></library_geometries><library_visual_scenes><visual_scene id="s">%s'
            '<instance_geometry url="#g"/>%s</visual_scene></library_visual_scenes>'
            '<scene><instance_visual_scene url="#s"/></scene></COLLADA>\n') % (
                3 * len(vs), pos, len(vs), len(fs), idx, nodes_open, nodes_close)


def stl(vs, fs):
    out = 'solid s\n'
    for f in fs:
        out += ' facet normal 0 0 1\n  outer loop\n'
        for i in f[:3]:
            out += '   vertex %.5g %.5g %.5g\n' % vs[i]
        out += '  endloop\n endfacet\n'
    return out + 'endsolid s\n'


def write(d, name, data):
    os.makedirs(d, exist_ok=True)
    mode = 'wb' if isinstance(data, bytes) else 'w'
    with open(os.path.join(d, name), mode) as f:
        f.write(data)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    dermis = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, 'build', 'bin', 'dermis')
    if not os.path.isdir(DATA):
        print('fuzz_seeds: %s is absent: no seeds from real assets (regression inputs only)' % DATA)
        return
    # Meshes: the 1,839-vertex bunny whole, and small pieces of it (small inputs mutate fastest).
    bunny = os.path.join(DATA, 'scans', 'bunny-npm-1839v.obj')
    vs, fs = read_obj(bunny)
    small_vs, small_fs = read_obj(bunny, 120)
    tiny_vs, tiny_fs = read_obj(bunny, 24)
    write(os.path.join(out, 'obj'), 'bunny1839.obj', obj_text(vs, fs))
    write(os.path.join(out, 'obj'), 'bunny120.obj', obj_text(small_vs, small_fs))
    write(os.path.join(out, 'obj'), 'bunny24.obj', obj_text(tiny_vs, tiny_fs))
    quads = [[0, 1, 2, 3], [1, 4, 5, 2]]
    quad_vs = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0)]
    write(os.path.join(out, 'obj'), 'quads.obj', 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n'
          'v 2 1 0\nf 1 2 3 4\nf -5 -2 -1 -4\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\n')
    for fmt in ('ascii', 'binary_little_endian', 'binary_big_endian'):
        write(os.path.join(out, 'ply'), 'bunny120_%s.ply' % fmt, ply_bytes(small_vs, small_fs, fmt))
        write(os.path.join(out, 'ply'), 'quads_%s.ply' % fmt, ply_bytes(quad_vs, quads, fmt))
    with open(os.path.join(DATA, 'scans', 'bun_zipper.ply'), 'rb') as f:
        zipper = f.read()
    write(os.path.join(out, 'ply'), 'bun_zipper_head.ply', zipper[:zipper.index(b'end_header') + 11])
    # glTF: the Khronos characters as they are.
    os.makedirs(os.path.join(out, 'gltf'), exist_ok=True)
    for name in sorted(os.listdir(os.path.join(DATA, 'gltf'))):
        shutil.copy(os.path.join(DATA, 'gltf', name), os.path.join(out, 'gltf', name))
    # Assimp: the first byte of an input picks the extension (tests/fuzz/fuzz_assimp.cpp):
    # 0 .dae, 1 .fbx, 2 .stl, 5 .off.
    write(os.path.join(out, 'assimp'), 'bunny120.dae', b'\x00' + collada(small_vs, small_fs, 3).encode())
    write(os.path.join(out, 'assimp'), 'bunny24.stl', b'\x02' + stl(tiny_vs, tiny_fs).encode())
    write(os.path.join(out, 'assimp'), 'bunny24.off', b'\x05' + (
        'OFF\n%d %d 0\n' % (len(tiny_vs), len(tiny_fs)) +
        ''.join('%.5g %.5g %.5g\n' % v for v in tiny_vs) +
        ''.join('%d %s\n' % (len(f), ' '.join(map(str, f))) for f in tiny_fs)).encode())
    # .dsurf: surfaces and characters fitted by the tool; the C API harness reads the same.
    if not os.access(dermis, os.X_OK):
        print('fuzz_seeds: %s not built: no .dsurf or asset-stream seeds' % dermis)
        return
    tmp = tempfile.mkdtemp()
    try:
        runs = [
            ('bunny1839.dsurf', [os.path.join(out, 'obj', 'bunny1839.obj'), '--control-vertices', '60']),
            ('RiggedSimple.dsurf', [os.path.join(DATA, 'gltf', 'RiggedSimple.glb')]),
            ('SimpleSkin.dsurf', [os.path.join(DATA, 'gltf', 'SimpleSkin.gltf')]),
        ]
        for name, args in runs:
            target = os.path.join(tmp, name)
            r = subprocess.run([dermis, 'fit'] + args + ['-o', target, '-q', '--threads', '1'],
                               capture_output=True, text=True)
            if r.returncode != 0:
                print('fuzz_seeds: dermis fit %s failed: %s' % (args[0], r.stderr.strip()))
                continue
            with open(target, 'rb') as f:
                data = f.read()
            write(os.path.join(out, 'dsurf'), name, data)
            write(os.path.join(out, 'capi'), name, data)
            # Its runtime archives (version 4, issue 17): f32 and 16-bit displacements.
            for suffix, flags in (('runtime', []), ('runtime16', ['--quantize-displacements'])):
                packed = os.path.join(tmp, name.replace('.dsurf', '.%s.dsurf' % suffix))
                r = subprocess.run([dermis, 'pack', target, '-o', packed, '-q'] + flags,
                                   capture_output=True, text=True)
                if r.returncode != 0:
                    print('fuzz_seeds: dermis pack %s failed: %s' % (name, r.stderr.strip()))
                    continue
                with open(packed, 'rb') as f:
                    archive = f.read()
                write(os.path.join(out, 'dsurf'), os.path.basename(packed), archive)
                write(os.path.join(out, 'capi'), os.path.basename(packed), archive)
            at = data.find(b'DASSET\0\0')
            if at >= 8:
                (n,) = struct.unpack('<Q', data[at - 8:at])
                write(os.path.join(out, 'asset_stream'), name.replace('.dsurf', '.asset'),
                      data[at:at + n])
    finally:
        shutil.rmtree(tmp)
    for h in sorted(os.listdir(out)):
        files = os.listdir(os.path.join(out, h))
        print('fuzz_seeds: %-13s %3d files, %8d bytes' % (
            h, len(files), sum(os.path.getsize(os.path.join(out, h, f)) for f in files)))


if __name__ == '__main__':
    main()
