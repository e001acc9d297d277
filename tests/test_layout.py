"""The library's shape (issue [1/6]): no circle, small modules, old names pointing to the new."""

import importlib
import pathlib
import subprocess
import sys
import warnings

import pytest

from dolfinx_contact_s2s import _moved

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_import_graph_has_layers_and_small_modules():
    # The project's own script, as anyone runs it; it reads the source, imports nothing.
    run = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "import_layers.py"), "--check"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "circles: none" in run.stdout
    assert "imports from a layer up or sideways: none" in run.stdout


def test_library_holds_no_paper_study():
    package = ROOT / "dolfinx_contact_s2s"
    names = {p.relative_to(package).as_posix() for p in package.rglob("*.py")}
    for gone in ("scenes.py", "scenes_multi.py", "scenes_hertz.py", "studies/__init__.py"):
        assert gone not in names


@pytest.mark.parametrize("old", sorted(_moved.RENAMED))
def test_renamed_module_warns_and_works(old):
    name = f"dolfinx_contact_s2s.{old}"
    sys.modules.pop(name, None)
    with pytest.warns(DeprecationWarning, match=_moved.RENAMED[old].replace(".", r"\.")):
        module = importlib.import_module(name)
    new = importlib.import_module(_moved.RENAMED[old])
    assert module is new
    for public in new.__all__:
        assert getattr(module, public) is getattr(new, public)
    sys.modules.pop(name, None)


@pytest.mark.parametrize("old", sorted(_moved.MOVED))
def test_moved_module_raises_naming_the_new_place(old):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ImportError, match=r"removed in dolfinx_contact_s2s 0\.3: see"):
            importlib.import_module(f"dolfinx_contact_s2s.{old}")


def test_old_names_the_readme_used():
    with pytest.raises(ImportError, match=r"dolfinx_contact_s2s\.meshing \(model_to_mesh"):
        from dolfinx_contact_s2s.scenes import model_to_mesh
    with pytest.raises(ImportError, match=r"dolfinx_contact_s2s\.assemble \(assemble_coupling"):
        from dolfinx_contact_s2s.petsc import assemble_coupling  # noqa: F401
    from dolfinx_contact_s2s import model_to_mesh
    from dolfinx_contact_s2s.meshing import model_to_mesh as new

    assert model_to_mesh is new
