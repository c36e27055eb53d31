"""``frictionkit models``: every law's fields start in the same column (README walk leftovers,
item 5: the Directional row's family text ran into its fields)."""
from frictionkit.catalog import catalog


def test_fields_column_is_aligned_for_every_law():
    cat = catalog()
    lines = cat.summary().splitlines()
    starts = {}
    for law in cat.laws:
        row = next(ln for ln in lines if ln.startswith(f"  {law.name} "))
        first = next(iter(law.fields))
        starts[law.name] = row.index(f" {first}") + 1
    # 2 spaces, the name in 15, a space, the family in 7, a space
    assert starts == {name: 2 + 15 + 1 + 7 + 1 for name in starts}
    assert "  Directional     any     positive, negative" in lines
