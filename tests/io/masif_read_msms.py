#!/usr/bin/env python3
"""fdmsurf's MSMS files read the way MaSIF reads MSMS's (numpy arrays, fields by position).

The reader below follows the layout MSMS documents and MaSIF's read_msms relies on: the vertex
count is the first field of the .vert file's third line; each vertex line gives position
(fields 0-2), normal (3-5), the 1-based atom (7) and the atom's xyzrn name (9); each face line
three 1-based vertex indices; the .area file, after one header line, the SES area in field 1
and the name in field 3. It runs `fdmsurf msms` with MaSIF's arguments on an xyzrn file and
checks every array against the input.

    masif_read_msms.py FDMSURF XYZRN WORKDIR      (exit 77: numpy is missing, test skipped)
"""
import os
import subprocess
import sys

try:
    import numpy as np
except ImportError:
    print("numpy is not installed: skipped")
    sys.exit(77)


def read_msms(file_root):
    with open(file_root + ".vert") as f:
        meshdata = f.read().rstrip().split("\n")
    nv = int(meshdata[2].split()[0])
    vertices = np.zeros((nv, 3))
    normalv = np.zeros((nv, 3))
    atom_id = [""] * nv
    res_id = [""] * nv
    for i in range(3, len(meshdata)):
        fields = meshdata[i].split()
        vi = i - 3
        vertices[vi] = [float(x) for x in fields[0:3]]
        normalv[vi] = [float(x) for x in fields[3:6]]
        atom_id[vi] = fields[7]
        res_id[vi] = fields[9]
        nv -= 1
    with open(file_root + ".face") as f:
        meshdata = f.read().rstrip().split("\n")
    nf = int(meshdata[2].split()[0])
    faces = np.zeros((nf, 3), dtype=int)
    for i in range(3, len(meshdata)):
        fields = meshdata[i].split()
        faces[i - 3] = [int(x) - 1 for x in fields[0:3]]
        nf -= 1
    assert nv == 0 and nf == 0, "counts in the headers differ from the lines"
    areas = {}
    with open(file_root + ".area") as f:
        next(f)
        for line in f:
            fields = line.split()
            areas[fields[3]] = float(fields[1])
    return vertices, faces, normalv, atom_id, res_id, areas


def main():
    fdmsurf, xyzrn, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    base = os.path.join(work, os.path.basename(xyzrn).split(".")[0])
    subprocess.run([fdmsurf, "msms", "-if", xyzrn, "-of", base, "-af", base,
                    "-probe_radius", "1.5", "-density", "3.0", "-hdensity", "3.0"],
                   check=True, stdout=subprocess.DEVNULL)
    vertices, faces, normals, atom_id, res_id, areas = read_msms(base)
    names, centres = [], []
    with open(xyzrn) as f:
        for line in f:
            fields = line.split()
            centres.append([float(x) for x in fields[0:3]] + [float(fields[3])])
            names.append(fields[5])
    centres = np.array(centres)
    atoms = np.array([int(a) for a in atom_id]) - 1
    assert atoms.min() >= 0 and atoms.max() < len(names), "atom numbers out of range"
    assert all(res_id[v] == names[atoms[v]] for v in range(len(atoms))), "names differ"
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=0.01), "normals not unit"
    dist = np.linalg.norm(vertices - centres[atoms, :3], axis=1)
    assert np.all(dist < centres[atoms, 3] + 3.01), "a vertex far from its atom"
    assert faces.min() >= 0 and faces.max() < len(vertices), "face index out of range"
    tri = vertices[faces]
    mesh_area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]),
                                     axis=1).sum()
    assert len(areas) == len(names) and set(areas) == set(names), "area names differ"
    total = sum(areas.values())
    assert abs(total - mesh_area) < 0.002 * mesh_area, (total, mesh_area)
    print(f"{os.path.basename(xyzrn)}: {len(vertices)} vertices, {len(faces)} faces, "
          f"SES {total:.1f} A^2 by {len(areas)} atoms: read as MaSIF reads MSMS")


if __name__ == "__main__":
    main()
