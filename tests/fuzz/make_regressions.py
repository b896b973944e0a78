#!/usr/bin/env python3
"""Small generated inputs that show each problem of the first fuzzing campaign (issue 19; the
original reproducers live outside the repository). Used by the CLI test cli.reliability
(tests/cli/reliability_test.cmake) and replayed through the fuzz harnesses (scripts/fuzz.sh
--replay). Every input must end cleanly: exit 1 with a message naming the file and the problem,
or a correct result.

Usage: make_regressions.py OUT_DIR [ARCHIVE]   (writes OUT_DIR/<harness>/<name>)

With ARCHIVE (a runtime archive, `dermis pack`), also damaged copies of it (issue 17): cut in
the middle, a node parent and a skin joint out of range, a node count larger than the file; each resealed with a correct checksum so that the body's own checks must refuse it.
"""
import base64
import json
import math
import os
import struct
import sys


def write(out, harness, name, data):
    d = os.path.join(out, harness)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), 'wb') as f:
        f.write(data if isinstance(data, bytes) else data.encode('utf-8', 'surrogateescape'))


def gltf(doc):
    return json.dumps(doc, separators=(',', ':'))


def buffer_uri(data):
    return 'data:application/octet-stream;base64,' + base64.b64encode(data).decode()


def skinned_triangle_doc(nodes):
    """One skinned triangle mesh (two joints) drawn by `nodes` nodes that share the mesh and skin."""
    pos = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0)
    joints = struct.pack('<12H', 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0)
    weights = struct.pack('<12f', 0.5, 0.5, 0, 0, 0.5, 0.5, 0, 0, 1, 0, 0, 0)
    ibm = struct.pack('<32f', *([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] * 2))
    data = pos + joints + weights + ibm
    views = [{'buffer': 0, 'byteOffset': 0, 'byteLength': 36},
             {'buffer': 0, 'byteOffset': 36, 'byteLength': 24},
             {'buffer': 0, 'byteOffset': 60, 'byteLength': 48},
             {'buffer': 0, 'byteOffset': 108, 'byteLength': 128}]
    accessors = [
        {'bufferView': 0, 'componentType': 5126, 'count': 3, 'type': 'VEC3',
         'min': [0, 0, 0], 'max': [1, 1, 0]},
        {'bufferView': 1, 'componentType': 5123, 'count': 3, 'type': 'VEC4'},
        {'bufferView': 2, 'componentType': 5126, 'count': 3, 'type': 'VEC4'},
        {'bufferView': 3, 'componentType': 5126, 'count': 2, 'type': 'MAT4'}]
    node_list = [{'name': 'j0', 'children': [1]}, {'name': 'j1', 'translation': [0, 1, 0]}]
    node_list += [{'mesh': 0, 'skin': 0} for _ in range(nodes)]
    return {'asset': {'version': '2.0'}, 'scene': 0,
            'scenes': [{'nodes': [0] + list(range(2, 2 + nodes))}], 'nodes': node_list,
            'meshes': [{'primitives': [{'attributes': {'POSITION': 0, 'JOINTS_0': 1,
                                                       'WEIGHTS_0': 2}}]}],
            'skins': [{'joints': [0, 1], 'inverseBindMatrices': 3}],
            'accessors': accessors, 'bufferViews': views,
            'buffers': [{'byteLength': len(data), 'uri': buffer_uri(data)}]}


def fnv1a64(data):
    h = 0xcbf29ce484222325
    for b in data:
        h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
    return h


def reseal(body):
    """A .dsurf body (everything before the checksum) with its FNV-1a 64 checksum appended."""
    return body + struct.pack('<Q', fnv1a64(body))


def archive_regressions(out, path):
    with open(path, 'rb') as f:
        data = f.read()
    assert data[:8] == b'DSURF\r\n\x1a' and struct.unpack('<I', data[8:12])[0] == 4, path
    body = bytearray(data[:-8])
    write(out, 'dsurf', 'archive_truncated.dsurf', reseal(bytes(body[:len(body) // 2])))
    # After the header (16 bytes): flags u32, 4 x f64 errors, node count u32 at 52, node 0's
    # parent i32 at 56.
    bad = bytearray(body)
    bad[52:56] = struct.pack('<I', 0x000fffff)
    write(out, 'dsurf', 'archive_node_count.dsurf', reseal(bytes(bad)))
    bad = bytearray(body)
    bad[56:60] = struct.pack('<i', 100000)
    write(out, 'dsurf', 'archive_parent_out_of_range.dsurf', reseal(bytes(bad)))
    # Skin 0's first joint: after the nodes (i32 parent, u64 name length, name) and the skin
    # count u32 and its joint count u32.
    (nodes,) = struct.unpack('<I', body[52:56])
    at = 56
    for _ in range(nodes):
        (length,) = struct.unpack('<Q', body[at + 4:at + 12])
        at += 12 + length
    (skins,) = struct.unpack('<I', body[at:at + 4])
    assert skins > 0, path
    bad = bytearray(body)
    bad[at + 8:at + 12] = struct.pack('<i', 100000)
    write(out, 'dsurf', 'archive_joint_out_of_range.dsurf', reseal(bytes(bad)))


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    out = sys.argv[1]
    if len(sys.argv) == 3:
        archive_regressions(out, sys.argv[2])
        return
    tri = 'v 0 0 0\nv 1 0 0\nv 0 1 0\n'
    # 8: index -2^63 (negating it overflowed), and the smallest relative index that fits.
    write(out, 'obj', 'llong_min_index.obj', tri + 'f 1 2 -9223372036854775808\n')
    write(out, 'obj', 'llong_max_index.obj', tri + 'f 1 2 9223372036854775807\n')
    # 11: coordinates near the double maximum: refused, not turned into (0,0,1) normals.
    write(out, 'obj', 'huge_coords.obj', 'v -1e308 0 0\nv 1e308 0 0\nv 0 1e308 0\nv 0 0 1e308\n'
          'f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n')
    # 7: one face of 20,000 vertices, one of them repeated at the very end (found, linear time).
    n = 20000
    ring = ''.join('v %.9f %.9f 0\n' % (math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n))
                   for i in range(n))
    write(out, 'obj', 'big_face_repeat.obj',
          ring + 'f ' + ' '.join(str(i + 1) for i in range(n)) + ' 1\n')
    # 2: JSON nested 5,000 deep in extras.
    deep = '{"asset":{"version":"2.0"},"extras":' + '[' * 5000 + ']' * 5000 + '}'
    write(out, 'gltf', 'deep_extras.gltf', deep)
    # 4: accessors without a bufferView: one of 2^26 VEC3 (1.5 GiB of doubles), and one of 2^21
    # used by 40 primitives (each decode counts against the budget).
    big = {'asset': {'version': '2.0'}, 'meshes': [{'primitives': [{'attributes': {'POSITION': 0}}]}],
           'nodes': [{'mesh': 0}], 'scenes': [{'nodes': [0]}],
           'accessors': [{'componentType': 5126, 'count': 1 << 26, 'type': 'VEC3',
                          'min': [0, 0, 0], 'max': [0, 0, 0]}]}
    write(out, 'gltf', 'unbacked_accessor.gltf', gltf(big))
    shared = {'asset': {'version': '2.0'},
              'meshes': [{'primitives': [{'attributes': {'POSITION': 0}}] * 40}],
              'nodes': [{'mesh': 0}], 'scenes': [{'nodes': [0]}],
              'accessors': [{'componentType': 5126, 'count': 1 << 21, 'type': 'VEC3',
                             'min': [0, 0, 0], 'max': [0, 0, 0]}]}
    write(out, 'gltf', 'shared_unbacked_40_primitives.gltf', gltf(shared))
    # 6: 4,000 nodes drawing one skinned mesh: valid, imported in linear time.
    write(out, 'gltf', 'instanced_skinned_4k_nodes.gltf', gltf(skinned_triangle_doc(4000)))
    # 3: a name that is not UTF-8 (JSON output must replace it, not abort).
    write(out, 'gltf', 'bad_utf8_name.gltf', b'{"asset":{"version":"2.0"},"nodes":[{"name":"bad\xff"}],'
          b'"scenes":[{"nodes":[0]}]}')
    # 12: a mesh whose every triangle has coincident corners: listed as unfitted, not dropped.
    pos = struct.pack('<9f', *([0.5] * 9)) * 10
    degenerate = {'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}],
                  'nodes': [{'mesh': 0}],
                  'meshes': [{'primitives': [{'attributes': {'POSITION': 0}}]}],
                  'accessors': [{'bufferView': 0, 'componentType': 5126, 'count': 30,
                                 'type': 'VEC3', 'min': [0.5] * 3, 'max': [0.5] * 3}],
                  'bufferViews': [{'buffer': 0, 'byteLength': len(pos)}],
                  'buffers': [{'byteLength': len(pos), 'uri': buffer_uri(pos)}]}
    write(out, 'gltf', 'degenerate_mesh.gltf', gltf(degenerate))
    # 9: Collada nodes nested 2,000 deep (first byte 0: the harness names it .dae).
    write(out, 'assimp', 'deep_nodes.dae', b'\x00' + (
        '<?xml version="1.0"?>\n<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" '
        'version="1.4.1"><library_visual_scenes><visual_scene id="s">' +
        ''.join('<node id="n%d">' % k for k in range(2000)) + '</node>' * 2000 +
        '</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/>'
        '</scene></COLLADA>\n').encode())
    # 14: bytes of no known format (first byte 9: .bin): refused before Assimp guesses.
    write(out, 'assimp', 'unknown_format.bin', b'\x09' + b'\xae' * 80)
    write(out, 'assimp', 'stl_solid.bin', b'\x09' + b'\x02solid t\n facet normal 0 0 1\n')
    # Found by fuzz_assimp (2026-12-02): a stray byte inside a Collada <p> list made Assimp
    # 5.2's integer reader allocate without bound; refused before Assimp.
    write(out, 'assimp', 'stray_byte_in_p.dae', b'\x00' + (
        '<?xml version="1.0"?>\n<COLLADA version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset>'
        '<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" '
        'count="9">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa" '
        'count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/>'
        '<param name="Z" type="float"/></accessor></technique_common></source><vertices id="v">'
        '<input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input '
        'semantic="VERTEX" source="#v" offset="0"/><p>0 1x 2</p></triangles></mesh></geometry>'
        '</library_geometries><library_visual_scenes><visual_scene id="s"><node id="n">'
        '<instance_geometry url="#g"/></node></visual_scene></library_visual_scenes><scene>'
        '<instance_visual_scene url="#s"/></scene></COLLADA>\n').encode())
    # Found by fuzz_assimp (2026-12-02): an OFF header declaring 10^35 faces made Assimp 5.2
    # reserve them (first byte 5: .off); refused before Assimp.
    write(out, 'assimp', 'off_face_count.off',
          b'\x05OFF\n3 333333333333333333333333333333333336 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n')
    write(out, 'assimp', 'off_no_keyword.off', b'\x05' + b'1' * 30 + b' 1 0\n0 0 0\n1 0 0\n')
    # Found by fuzz_assimp (2026-12-02): an accessor whose stride reads past its array made
    # Assimp 5.2 read past the heap block; refused before Assimp.
    write(out, 'assimp', 'accessor_past_array.dae', b'\x00' + (
        '<?xml version="1.0"?>\n<COLLADA version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset>'
        '<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" '
        'count="9">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa" '
        'count="3" stride="32"><param name="X" type="float"/><param name="Y" type="float"/>'
        '<param name="Z" type="float"/></accessor></technique_common></source><vertices id="v">'
        '<input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input '
        'semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry>'
        '</library_geometries><library_visual_scenes><visual_scene id="s"><node id="n">'
        '<instance_geometry url="#g"/></node></visual_scene></library_visual_scenes><scene>'
        '<instance_visual_scene url="#s"/></scene></COLLADA>\n').encode())


if __name__ == '__main__':
    main()
