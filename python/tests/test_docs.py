"""docs/python.md's example: the table it prints is what the bundled spheroid run gives, to
the digits printed, and the README's three-line example runs."""

import re


def _half_digit(s: str) -> float:
    mantissa = s.lower().split("e")
    exp = int(mantissa[1]) if len(mantissa) == 2 else 0
    decimals = len(mantissa[0].split(".")[1]) if "." in mantissa[0] else 0
    return 0.5 * 10.0 ** (exp - decimals)


def test_the_example_table_is_what_the_run_gives(root, spheroid_py):
    text = (root / "docs" / "python.md").read_text()
    start = text.index("<!-- the example's output: asserted by python/tests/test_docs.py -->")
    rows = [
        [c.strip() for c in line.strip().strip("|").split("|")]
        for line in text[start:].splitlines()[1:]
        if line.startswith("|")
    ][2:]
    assert len(rows) >= 3
    df = spheroid_py.coefficients
    for name, value, sigma, unit in rows:
        got = df.filter(df["name"] == name).row(0, named=True)
        assert abs(float(value) - got["value"]) <= _half_digit(value) * (1 + 1e-9), (name, value, got)
        assert abs(float(sigma) - got["sigma"]) <= _half_digit(sigma) * (1 + 1e-9), (name, sigma, got)
        assert unit == got["unit"]


def test_the_readme_example_runs(root, tmp_path, monkeypatch, capsys):
    text = (root / "README.md").read_text()
    block = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    assert len(block.strip().splitlines()) == 3
    monkeypatch.chdir(tmp_path)
    exec(block.replace('"configs/', f'"{root}/configs/'), {})
    assert "Yvd" in capsys.readouterr().out
    assert (tmp_path / "out" / "spheroid" / "results.json").is_file()
