"""Exchange formats: glTF 2.0 output of `cover evaluate` read back by VTK's vtkGLTFReader (one
block per leaf present, each the leaf's triangles of Model.evaluate(leaf_ids=True), at the same
positions rounded to float); 3MF read back with zipfile and ElementTree from the 3MF core and
materials specification; cover.write_mesh in every format."""

import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

import cover
from conftest import BUILD_DIR, MODELS, cli_json, run_cli


@pytest.mark.parametrize("ext", [".glb", ".gltf"])
def test_evaluate_gltf_reads_back_in_vtk(tmp_path, ext):
    io = pytest.importorskip("vtkmodules.vtkIOGeometry")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    out = tmp_path / ("scene" + ext)
    j = cli_json("evaluate", MODELS / "default.json", "-o", out)
    V, F, leaf = cover.load(MODELS / "default.json").evaluate(leaf_ids=True)
    assert j["faces"] == len(F)
    reader = io.vtkGLTFReader()
    reader.SetFileName(str(out))
    reader.Update()
    it = reader.GetOutput().NewIterator()
    it.InitTraversal()
    blocks = []
    while not it.IsDoneWithTraversal():
        blocks.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    leaves = sorted(set(int(l) for l in leaf))
    assert len(blocks) == len(leaves)
    for block, l in zip(blocks, leaves):
        # VTK applies the node's rotation (Cover's z up shown as glTF's y up): undo it.
        P = vtk_to_numpy(block.GetPoints().GetData()).astype(np.float64)
        P = np.stack([P[:, 0], -P[:, 2], P[:, 1]], axis=1)
        cells = block.GetPolys()
        tris = vtk_to_numpy(cells.GetConnectivityArray()).reshape(-1, 3)
        mine = F[leaf == l]
        assert len(tris) == len(mine)
        np.testing.assert_allclose(P[tris], V[mine].astype(np.float32), rtol=0, atol=1e-5)


def test_write_mesh_every_format_reads_back(tmp_path):
    io = pytest.importorskip("vtkmodules.vtkIOGeometry")
    model = cover.load(MODELS / "default.json")
    V, F, leaf = model.evaluate(leaf_ids=True)
    for ext in (".off", ".obj", ".ply", ".stl", ".glb", ".gltf", ".3mf"):
        cover.write_mesh(tmp_path / ("m" + ext), V, F, None)
    # .off round-trips exactly (read back by the CLI's reader via cover.load).
    V2, F2 = cover.load(tmp_path / "m.off").evaluate()
    np.testing.assert_array_equal(V2[np.lexsort(V2.T)], V[np.lexsort(V.T)])
    # Leaf ids: a material per leaf in glTF, read back by VTK as one block per leaf.
    cover.write_mesh(tmp_path / "leaves.glb", V, F, leaf)
    reader = io.vtkGLTFReader()
    reader.SetFileName(str(tmp_path / "leaves.glb"))
    reader.Update()
    assert reader.GetOutput().GetNumberOfBlocks() >= 1
    it = reader.GetOutput().NewIterator()
    it.InitTraversal()
    count = 0
    while not it.IsDoneWithTraversal():
        count += 1
        it.GoToNextItem()
    assert count == len(set(leaf.tolist()))
    with pytest.raises(cover.InputError, match="cannot carry face labels"):
        cover.write_mesh(tmp_path / "m.off", V, F, leaf)
    with pytest.raises(cover.InputError, match="unsupported mesh format"):
        cover.write_mesh(tmp_path / "m.3ds", V, F)
    with pytest.raises(cover.InputError, match="leaf_ids"):
        cover.write_mesh(tmp_path / "m.ply", V, F, leaf[:-1])


CORE = "{http://schemas.microsoft.com/3dmanufacturing/core/2015/02}"


def test_evaluate_3mf_reads_back_with_a_material_per_leaf(tmp_path):
    out = tmp_path / "scene.3mf"
    j = cli_json("evaluate", MODELS / "default.json", "-o", out)
    V, F, leaf = cover.load(MODELS / "default.json").evaluate(leaf_ids=True)
    with zipfile.ZipFile(out) as z:
        assert "3D/3dmodel.model" in z.namelist()
        root = ET.fromstring(z.read("3D/3dmodel.model"))
    assert root.get("unit") == "millimeter"
    resources = root.find(CORE + "resources")
    objects = resources.findall(CORE + "object")
    assert len(objects) == 1 and len(root.find(CORE + "build")) == 1
    mesh = objects[0].find(CORE + "mesh")
    P = np.array([[float(v.get(a)) for a in "xyz"] for v in mesh.find(CORE + "vertices")])
    T = mesh.find(CORE + "triangles")
    tris = np.array([[int(t.get(a)) for a in ("v1", "v2", "v3")] for t in T])
    assert len(tris) == j["faces"] == len(F)
    np.testing.assert_allclose(P[tris], V[F].astype(np.float32), rtol=0, atol=1e-5)
    # Each triangle's base material is its leaf; one opaque colour per leaf, all distinct.
    materials = resources.find(CORE + "basematerials")
    group = materials.get("id")
    assert all(t.get("pid") == group for t in T)
    np.testing.assert_array_equal([int(t.get("p1")) for t in T], leaf)
    colours = [m.get("displaycolor") for m in materials]
    assert [m.get("name") for m in materials] == [f"leaf_{i}" for i in range(len(colours))]
    assert all(c.endswith("FF") for c in colours) and len(set(colours)) == len(colours)
    # The same mesh gives the same bytes (content-derived UUIDs), for any thread count.
    again = tmp_path / "again.3mf"
    cli_json("evaluate", MODELS / "default.json", "-o", again, "--threads", 1)
    assert again.read_bytes() == out.read_bytes()


class _TrimeshLike:  # the attributes trimesh.Trimesh and Open3D expose
    def __init__(self, V, F, faces_name="faces"):
        self.vertices = V
        setattr(self, faces_name, F)


class _MeshioLike:  # meshio.Mesh: points and cells_dict
    def __init__(self, V, F):
        self.points = V
        self.cells_dict = {"triangle": F}


def test_mesh_objects_from_other_libraries_and_to_vtk():
    """cover.mesh takes trimesh-, Open3D- and meshio-shaped objects and VTK polydata (checked
    with VTK's own cube source, quads triangulated by VTK); to_vtk gives polydata VTK measures
    the same volume of (vtkMassProperties, an independent path)."""
    from vtkmodules.vtkFiltersCore import vtkMassProperties, vtkTriangleFilter
    from vtkmodules.vtkFiltersSources import vtkCubeSource
    part = cover.load(MODELS / "torus.off")
    V, F = part.evaluate()
    volume = part.volume()
    for obj in (_TrimeshLike(V, F), _TrimeshLike(V, F, "triangles"), _MeshioLike(V, F)):
        assert cover.mesh(obj).volume() == pytest.approx(volume, rel=1e-12)
    poly = cover.to_vtk(V, F)
    assert poly.GetNumberOfPoints() == len(V) and poly.GetNumberOfCells() == len(F)
    mass = vtkMassProperties()
    mass.SetInputData(poly)
    mass.Update()
    assert mass.GetVolume() == pytest.approx(volume, rel=1e-9)
    assert cover.mesh(poly).volume() == pytest.approx(volume, rel=1e-12)
    cube = vtkCubeSource()
    cube.SetXLength(2)
    cube.Update()
    assert cover.mesh(cube.GetOutput()).volume() == pytest.approx(2)
    with pytest.raises(TypeError, match="mesh object"):
        cover.mesh(object())
    with pytest.raises(cover.InputError, match="triangle"):
        m = _MeshioLike(V, F)
        m.cells_dict = {"quad": F}
        cover.mesh(m)
    with pytest.raises(ValueError, match=r"F: expected an array of shape \(m, 3\)"):
        cover.to_vtk(V, F[:, :2])


def test_octree_equals_the_cli_and_saves_every_format(tmp_path):
    """Model.octree gives the nodes `cover octree` writes (the .json files are byte-equal);
    its arrays hang together (children eight in a row, one level down); .htg reads back in
    VTK's HyperTreeGrid reader with as many cells."""
    part = cover.load(MODELS / "default.json")
    tree = part.octree(5)
    assert isinstance(tree, cover.Octree) and tree.depth == 5 and len(tree) > 8
    ours, cli = tmp_path / "ours.json", tmp_path / "cli.json"
    tree.save(ours)
    run_cli("octree", MODELS / "default.json", "--depth", 5, "-o", cli, "--quiet")
    assert ours.read_bytes() == cli.read_bytes()
    inner = np.nonzero(tree.first_child)[0]
    assert (tree.state[inner] == 2).all()
    kids = tree.first_child[inner][:, None] + np.arange(8)
    assert (tree.level[kids] == tree.level[inner][:, None] + 1).all()
    counts = tree.leaf_counts
    assert sum(counts.values()) == len(tree) - len(inner) and counts["full"] > 0
    full = tree.state == 1
    assert (tree.occupancy[full] == 1).all()
    htg = tmp_path / "tree.htg"
    tree.save(htg)
    from vtkmodules.vtkIOXML import vtkXMLHyperTreeGridReader
    reader = vtkXMLHyperTreeGridReader()
    reader.SetFileName(str(htg))
    reader.Update()
    assert reader.GetOutput().GetNumberOfVertices() == len(tree)
    # .bt: byte-equal to the CLI's, which liboctomap reads back in the C++ tests.
    with pytest.raises(cover.InputError, match="OctoMap"):
        tree.save(tmp_path / "ours.bt")
    part.octree(5, "octomap").save(tmp_path / "ours.bt")
    run_cli("octree", MODELS / "default.json", "--depth", 5, "-o", tmp_path / "cli.bt", "--quiet")
    assert (tmp_path / "ours.bt").read_bytes() == (tmp_path / "cli.bt").read_bytes()
    with pytest.raises(cover.InputError, match="depth"):
        part.octree(17)


def test_write_voxels_reads_back_in_numpy_vtk_and_the_sidecar(tmp_path):
    part = cover.load(MODELS / "torus.off")
    grid = part.voxelize(24)
    bounds = part.voxel_bounds(24)
    for ext in (".npy", ".vti", ".raw", ".binvox"):
        cover.write_voxels(tmp_path / ("g" + ext), grid, bounds)
    assert np.array_equal(np.load(tmp_path / "g.npy"), grid.astype(np.uint8))
    raw = np.fromfile(tmp_path / "g.raw", dtype=np.uint8).reshape(24, 24, 24)
    assert np.array_equal(raw, grid)
    import json
    side = json.loads((tmp_path / "g.raw.json").read_text())
    assert side["bounds"]["min"] == list(bounds[:3]) and side["bounds"]["size"] == bounds[3]
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader
    reader = vtkXMLImageDataReader()
    reader.SetFileName(str(tmp_path / "g.vti"))
    reader.Update()
    image = reader.GetOutput()
    cells = vtk_to_numpy(image.GetCellData().GetArray("occupancy")).reshape(24, 24, 24)
    assert np.array_equal(cells.transpose(2, 1, 0), grid)  # VTK: x fastest
    assert image.GetOrigin() == pytest.approx(bounds[:3])
    cli = tmp_path / "cli.binvox"
    run_cli("voxelize", MODELS / "torus.off", "--res", 24, "-o", cli, "--quiet")
    assert cli.read_bytes() == (tmp_path / "g.binvox").read_bytes()
    with pytest.raises(cover.InputError, match="cubic"):
        cover.write_voxels(tmp_path / "bad.npy", grid[:, :, :3], bounds)
    with pytest.raises(cover.InputError, match="bounds"):
        cover.write_voxels(tmp_path / "bad.npy", grid, (0, 0, 0, -1))
    assert not (tmp_path / "bad.npy").exists()


def test_write_voxels_non_cubic_and_zarr_equal_the_cli(tmp_path):
    """A non-cubic grid (dims=) with its Model.voxel_lattice: the .zarr store (read by the zarr
    package) and the .raw with its sidecar equal `cover voxelize --dims` file for file; the
    lattice's centres are the ones voxelize classified."""
    zarr = pytest.importorskip("zarr")
    part = cover.load(MODELS / "default.json")
    grid = part.voxelize(dims=(20, 31, 9))
    lattice = part.voxel_lattice(dims=(20, 31, 9))
    assert isinstance(lattice, cover.VoxelLattice) and lattice.dims == (20, 31, 9)
    assert lattice.cube_size is None and part.voxel_lattice(16).cube_size is not None
    for ext in (".zarr", ".raw", ".vti", ".npy"):
        cover.write_voxels(tmp_path / ("py" + ext), grid, lattice=lattice, chunk=8)
        run_cli("voxelize", MODELS / "default.json", "--dims", "20,31,9", "-o",
                tmp_path / ("cli" + ext), "--chunk", 8, "--quiet")
    stored = zarr.open(str(tmp_path / "py.zarr"), mode="r")
    assert np.array_equal(stored[:], grid.astype(np.uint8))
    for name in sorted(p.name for p in (tmp_path / "cli.zarr").iterdir()):
        assert (tmp_path / "py.zarr" / name).read_bytes() == \
            (tmp_path / "cli.zarr" / name).read_bytes(), name
    for name in ("py.raw", "py.raw.json", "py.vti", "py.npy"):
        cli = tmp_path / name.replace("py", "cli", 1)
        assert (tmp_path / name).read_bytes() == cli.read_bytes(), name
    # (origin, spacing) alone does as well; a cubic grid may give bounds or its lattice.
    cover.write_voxels(tmp_path / "pair.raw", grid, lattice=(lattice.origin, lattice.spacing))
    assert (tmp_path / "pair.raw.json").read_bytes() == (tmp_path / "cli.raw.json").read_bytes()
    cube = part.voxelize(12)
    cover.write_voxels(tmp_path / "a.binvox", cube, part.voxel_bounds(12))
    cover.write_voxels(tmp_path / "b.binvox", cube, lattice=part.voxel_lattice(12))
    assert (tmp_path / "a.binvox").read_bytes() == (tmp_path / "b.binvox").read_bytes()
    for kwargs, word in [({}, "exactly one"),
                         ({"bounds": part.voxel_bounds(12)}, "non-cubic"),
                         ({"lattice": (lattice.origin, 0.0)}, "spacing"),
                         ({"lattice": (lattice.origin, 1.0, (3, 4, 5))}, "dims"),
                         ({"lattice": lattice, "chunk": 0}, "chunk")]:
        with pytest.raises(cover.InputError, match=word):
            cover.write_voxels(tmp_path / "bad.zarr", grid, **kwargs)
    with pytest.raises(cover.InputError, match="cubic"):
        cover.write_voxels(tmp_path / "bad.binvox", grid, lattice=lattice)
    assert not (tmp_path / "bad.zarr").exists() and not (tmp_path / "bad.binvox").exists()


def test_write_voxels_vdb_reads_back_in_pyopenvdb(tmp_path, monkeypatch):
    """The .vdb route (Cover's OpenVDB plugin) read by OpenVDB's own Python module: the same
    voxels, the voxel size and the first voxel's centre of the bounds."""
    vdb = pytest.importorskip("pyopenvdb")
    monkeypatch.setenv("COVER_PLUGIN_DIR", str(BUILD_DIR / "lib" / "cover"))
    part = cover.load(MODELS / "torus.off")
    grid, bounds = part.voxelize(24), part.voxel_bounds(24)
    cover.write_voxels(tmp_path / "g.vdb", grid, bounds)
    read = vdb.read(str(tmp_path / "g.vdb"), "occupancy")
    dense = np.zeros(grid.shape, bool)
    read.copyToArray(dense, ijk=(0, 0, 0))
    assert np.array_equal(dense, grid) and read.activeVoxelCount() == grid.sum()
    h = bounds[3] / 24
    assert read.transform.voxelSize() == pytest.approx((h, h, h))
    assert read.transform.indexToWorld((0, 0, 0)) == pytest.approx(np.array(bounds[:3]) + h / 2)


def test_evaluate_result_unpacks_and_saves(tmp_path):
    part = cover.load(MODELS / "default.json")
    result = part.evaluate(leaf_ids=True)
    V, F, L = result  # the tuple as before
    assert isinstance(result, cover.MeshResult) and isinstance(result, tuple)
    result.save(tmp_path / "e.ply")
    cover.write_mesh(tmp_path / "w.ply", V, F, L)
    assert (tmp_path / "e.ply").read_bytes() == (tmp_path / "w.ply").read_bytes()
    run_cli("evaluate", MODELS / "default.json", "--leaf-ids", "-o", tmp_path / "c.ply", "--quiet")
    assert (tmp_path / "c.ply").read_bytes() == (tmp_path / "e.ply").read_bytes()
    plain = part.evaluate()
    plain.save(tmp_path / "p.ply")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOPLY import vtkPLYReader
    reader = vtkPLYReader()
    reader.SetFileName(str(tmp_path / "p.ply"))
    reader.Update()
    out = reader.GetOutput()
    assert out.GetNumberOfCells() == len(plain[1])
    assert np.allclose(vtk_to_numpy(out.GetPoints().GetData()), plain[0], rtol=1e-6, atol=1e-6)


def test_scene_colours_reach_renders_gltf_3mf_and_pickles(tmp_path):
    """A node's "color" colours every leaf below it unless a nearer node has its own: render,
    glTF, 3MF, Model.leaf_colours and the pickled Model agree."""
    import json
    import pickle
    scene = {"union": [
        {"difference": [{"box": {"min": [0, 0, 0], "max": [2, 2, 2]}, "color": "#ff8000"},
                        {"sphere": {"center": [2, 2, 2], "radius": 1.2}}],
         "color": [0, 0.5, 1]},
        {"cylinder": {"base": [0, 0, 0], "top": [0, 0, 3], "radius": 0.5}}]}
    path = tmp_path / "coloured.json"
    path.write_text(json.dumps(scene))
    m = cover.load(path)
    palette = cover.load(MODELS / "default.json").leaf_colours
    np.testing.assert_array_equal(m.leaf_colours, [[255, 128, 0], [0, 128, 255], palette[2]])
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(m)).leaf_colours, m.leaf_colours)
    # Render: the box's faces are shades of its colour (r = 2g, b = 0).
    img = m.render(96, 96, samples=1).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    assert ((b == 0) & (g > 20) & (np.abs(r - 2 * g) <= 2)).sum() > 100
    # 3MF: base materials in those colours, opaque.
    cli_json("evaluate", path, "-o", tmp_path / "c.3mf")
    with zipfile.ZipFile(tmp_path / "c.3mf") as z:
        root = ET.fromstring(z.read("3D/3dmodel.model"))
    materials = root.find(CORE + "resources").find(CORE + "basematerials")
    want = ["#%02X%02X%02XFF" % tuple(c) for c in m.leaf_colours]
    assert [x.get("displaycolor") for x in materials] == want
    # glTF: the same materials as write_mesh with colours=m.leaf_colours (and not the palette).
    cli_json("evaluate", path, "-o", tmp_path / "c.gltf")
    V, F, leaf = m.evaluate(leaf_ids=True)
    cover.write_mesh(tmp_path / "w.gltf", V, F, leaf, colours=m.leaf_colours)
    cover.write_mesh(tmp_path / "p.gltf", V, F, leaf)
    mats = json.loads((tmp_path / "c.gltf").read_text())["materials"]
    assert mats == json.loads((tmp_path / "w.gltf").read_text())["materials"]
    assert mats != json.loads((tmp_path / "p.gltf").read_text())["materials"]
    # Bad colours: one line naming the JSON path.
    scene["union"][1]["color"] = [2, 0, 0]
    path.write_text(json.dumps(scene))
    with pytest.raises(cover.InputError, match=r"/union/1/color/0: expected a number from 0 to 1"):
        cover.load(path)
    scene["union"][1]["color"] = "red"
    path.write_text(json.dumps(scene))
    with pytest.raises(cover.InputError, match=r"/union/1/color: expected \[r, g, b\]"):
        cover.load(path)
