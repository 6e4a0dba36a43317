"""Every shipped 3MF is read by the 3MF Consortium's own library, lib3mf, in strict mode (its
conformance check) with no warning, and holds one named object per part — regression for the
production extension's attributes trimesh writes ("Invalid Attribute in namespace": lib3mf
rejected all 10 assemblies in strict mode)."""

import lib3mf

from transplanter.shop import threemf


def _strict(data: bytes) -> list[str]:
    """The part numbers of the build items, read in strict mode; raises on a non-conforming file."""
    model = lib3mf.get_wrapper().CreateModel()
    reader = model.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromBuffer(bytearray(data))
    assert reader.GetWarningCount() == 0, [reader.GetWarning(i) for i in range(reader.GetWarningCount())]
    items, names = model.GetBuildItems(), []
    while items.MoveNext():
        item = items.GetCurrent()
        assert item.GetObjectResource().GetName() == item.GetPartNumber()
        names.append(item.GetPartNumber())
    return names


def test_every_shipped_3mf_is_strict_valid(built):
    files = sorted(built.rglob("*.3mf"))
    assert len(files) >= 9
    for path in files:
        data = path.read_bytes()
        assert sorted(_strict(data)) == sorted(threemf.read_assembly(data)), path.name
