"""The documentation site builds offline, strictly, with every page and figure.

Builds docs/ with ``mkdocs build --strict`` into a temporary directory (the same
command as ``make docs``, which writes site/) and checks that

* the build exits 0 (strict: a broken link, image path or nav entry fails it);
* every page in mkdocs.yml's nav produced its HTML file;
* every ``docs/figures/*.png`` that the Markdown references was copied, and the page
  that references it has an ``<img>`` pointing at the copy;
* no built page or stylesheet loads anything (script, stylesheet, font, image, frame)
  from another host, so the site works without a network.  Plain ``<a href>`` links
  to other sites are allowed: they are only followed when clicked.

Takes about a second.
"""

from __future__ import annotations

import posixpath
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
CONFIG = ROOT / "mkdocs.yml"

EXTERNAL = re.compile(r"^\s*(https?:)?//", re.IGNORECASE)
# Markdown images ![alt](path "title") and raw <img src="path">.
MD_IMAGE = re.compile(r"!\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+[\"'][^)]*[\"'])?\s*\)")
HTML_IMG = re.compile(r"<img\b[^>]*\bsrc\s*=\s*[\"']([^\"']+)[\"']", re.IGNORECASE)
CSS_URL = re.compile(r"(?:url\(\s*[\"']?|@import\s+[\"'])\s*((?:https?:)?//[^\"')\s]+)", re.I)


def _config() -> dict:
    yaml = pytest.importorskip("yaml")  # PyYAML comes with mkdocs
    return yaml.safe_load(CONFIG.read_text(encoding="utf-8"))


def _nav_pages(nav) -> list[str]:
    """The Markdown files named in the nav (nested sections flattened)."""
    pages: list[str] = []
    for entry in nav:
        if isinstance(entry, str):
            pages.append(entry)
        elif isinstance(entry, dict):
            for value in entry.values():
                if isinstance(value, str):
                    pages.append(value)
                else:
                    pages.extend(_nav_pages(value))
    return [p for p in pages if not EXTERNAL.match(p)]


def _output_path(page: str, directory_urls: bool) -> str:
    """Where mkdocs writes the HTML for ``page`` (relative to site_dir)."""
    stem = page[: -len(".md")]
    name = posixpath.basename(stem)
    if name in ("index", "README"):
        return posixpath.join(posixpath.dirname(stem), "index.html")
    return f"{stem}/index.html" if directory_urls else f"{stem}.html"


def _figure_refs() -> dict[str, set[str]]:
    """docs/figures/*.png referenced from each Markdown page: {page: {figures/x.png}}."""
    refs: dict[str, set[str]] = {}
    for md in sorted(DOCS.rglob("*.md")):
        page = md.relative_to(DOCS).as_posix()
        text = md.read_text(encoding="utf-8")
        for target in MD_IMAGE.findall(text) + HTML_IMG.findall(text):
            if EXTERNAL.match(target):
                continue
            resolved = posixpath.normpath(
                posixpath.join(posixpath.dirname(page), target.split("#")[0])
            )
            if resolved.startswith("figures/") and resolved.endswith(".png"):
                refs.setdefault(page, set()).add(resolved)
    return refs


class _Loads(HTMLParser):
    """Collects what a page loads by itself: scripts, stylesheets, icons, images…"""

    def __init__(self) -> None:
        super().__init__()
        self.loaded: list[tuple[str, str]] = []
        self.images: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = {k: (v or "") for k, v in attrs}
        if tag == "link" and "href" in a:
            # rel="stylesheet", "icon", "preload", …: all fetched by the browser
            # (canonical/alternate are not fetched, but keep them local too).
            self.loaded.append((f"link rel={a.get('rel', '')}", a["href"]))
        for attr in ("src", "data-src", "srcset", "poster"):
            if attr in a and tag in ("script", "img", "iframe", "source", "video",
                                     "audio", "embed", "track", "input"):
                self.loaded.append((f"{tag} {attr}", a[attr]))
        if tag == "object" and "data" in a:
            self.loaded.append(("object data", a["data"]))
        if tag == "img" and "src" in a:
            self.images.append(a["src"])
        if "style" in a:
            for url in CSS_URL.findall(a["style"]):
                self.loaded.append((f"{tag} style", url))

    def handle_data(self, data):
        # Inline <style> blocks (and harmlessly, inline scripts' text).
        if self.lasttag == "style":
            for url in CSS_URL.findall(data):
                self.loaded.append(("style", url))


@pytest.fixture(scope="module")
def built_site(tmp_path_factory) -> Path:
    site = tmp_path_factory.mktemp("site")
    try:
        proc = subprocess.run(
            [sys.executable, "-m", "mkdocs", "build", "--strict",
             "--config-file", str(CONFIG), "--site-dir", str(site)],
            cwd=ROOT, capture_output=True, text=True, timeout=120,
        )
    except FileNotFoundError as exc:  # pragma: no cover
        pytest.fail(f"cannot run mkdocs: {exc}")
    assert proc.returncode == 0, (
        f"mkdocs build --strict failed (exit {proc.returncode}); "
        f"install it with `make docs`.\n{proc.stdout}\n{proc.stderr}"
    )
    return site


def test_every_nav_page_is_built(built_site):
    cfg = _config()
    pages = _nav_pages(cfg["nav"])
    assert "index.md" in pages
    for page in pages:
        assert (DOCS / page).is_file(), f"nav names {page}, which is not in docs/"
    directory_urls = cfg.get("use_directory_urls", True)
    missing = [p for p in pages if not (built_site / _output_path(p, directory_urls)).is_file()]
    assert not missing, f"no HTML built for nav pages {missing}"


def test_referenced_figures_are_copied_and_shown(built_site):
    cfg = _config()
    directory_urls = cfg.get("use_directory_urls", True)
    refs = _figure_refs()
    for page, figures in refs.items():
        for fig in figures:
            assert (DOCS / fig).is_file(), f"{page} references {fig}, which does not exist"
            copy = built_site / fig
            assert copy.is_file(), f"{fig} (used by {page}) was not copied into the site"
            assert copy.read_bytes() == (DOCS / fig).read_bytes()
        html_file = built_site / _output_path(page, directory_urls)
        if not html_file.is_file():  # page outside the nav is still built
            html_file = built_site / _output_path(page, not directory_urls)
        parser = _Loads()
        parser.feed(html_file.read_text(encoding="utf-8"))
        html_dir = posixpath.dirname(html_file.relative_to(built_site).as_posix())
        shown = {posixpath.normpath(posixpath.join(html_dir, src)) for src in parser.images
                 if not EXTERNAL.match(src)}
        assert figures <= shown, f"{html_file.name}: no <img> for {sorted(figures - shown)}"


def test_figures_directory_pngs_all_used():
    """Every PNG kept in docs/figures/ is shown somewhere (no orphaned figures)."""
    used = set().union(*_figure_refs().values()) if _figure_refs() else set()
    on_disk = {p.relative_to(DOCS).as_posix() for p in (DOCS / "figures").glob("*.png")}
    assert on_disk <= used, f"figures not referenced by any page: {sorted(on_disk - used)}"


def test_site_loads_nothing_from_the_network(built_site):
    offenders: list[str] = []
    for html_file in sorted(built_site.rglob("*.html")):
        parser = _Loads()
        parser.feed(html_file.read_text(encoding="utf-8"))
        rel = html_file.relative_to(built_site)
        for what, url in parser.loaded:
            if any(EXTERNAL.match(u.split()[0]) for u in url.split(",") if u.strip()):
                offenders.append(f"{rel}: {what} -> {url}")
    for css in sorted(built_site.rglob("*.css")):
        for url in CSS_URL.findall(css.read_text(encoding="utf-8", errors="replace")):
            offenders.append(f"{css.relative_to(built_site)}: url -> {url}")
    assert not offenders, "the site fetches from other hosts:\n" + "\n".join(offenders)


def test_validation_figures_script_smoke(tmp_path):
    """docs/figures/make_validation_figures.py cannot rot: its two cheap
    figures (patch test, the paper's Figure 1) are redrawn into a temporary
    directory and are PNGs (the others re-solve the Hertz and
    Cattaneo–Mindlin validation cases, minutes each)."""
    script = DOCS / "figures" / "make_validation_figures.py"
    subprocess.run(
        [sys.executable, str(script), "--only", "patch_test", "--only", "two_cubes_figure1",
         "--out", str(tmp_path)], check=True, capture_output=True, text=True, timeout=300,
    )
    for name in ("patch_test.png", "two_cubes_figure1.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


#: What the generated API reference must document (heading id -> a phrase of
#: its docstring): the entry points of a user's script.
API = {
    "bemcontact.problemfile.reader.load_problem": "Read and check a problem file.",
    "bemcontact.problemfile.reader.ProblemFile.solve": "Solve the file's problem as",
    "bemcontact.contact.problem.ContactProblem": "",
    "bemcontact.output.write.write_results": "Write the result files into",
    "bemcontact.output.plot.plot_frame_tractions": "zoomed to the contact zone",
    "bemcontact.output.vtu.geometric_values": "at the mesh's geometric nodes",
    "bemcontact.validation.reference.contact.hertz": "",
}


def test_api_reference_is_generated_from_the_docstrings(built_site):
    """api.md's ``:::`` directives became documented objects (mkdocstrings):
    each entry point has its anchor and its docstring's text, no directive
    is left unrendered, and the page is in the nav."""
    assert "api.md" in _nav_pages(_config()["nav"])
    page = (built_site / "api.html").read_text(encoding="utf-8")
    assert ":::" not in page
    text = re.sub(r"<[^>]+>", " ", page)
    for anchor, phrase in API.items():
        assert f'id="{anchor}"' in page, f"api.html: no entry {anchor}"
        assert " ".join(phrase.split()) in " ".join(text.split()), f"api.html: {anchor}: {phrase!r}"
    documented = re.findall(r'id="(bemcontact\.[\w.]+)"', page)
    assert len(documented) >= 80, len(documented)


def test_gallery_shows_every_example():
    """docs/gallery.md names every example in examples/ and shows a figure."""
    text = (DOCS / "gallery.md").read_text(encoding="utf-8")
    examples = sorted(p.name for p in (ROOT / "examples").iterdir()
                      if p.suffix in (".py", ".toml"))
    missing = [e for e in examples if f"examples/{e}" not in text]
    assert not missing, f"gallery.md does not show {missing}"
    assert len(MD_IMAGE.findall(text)) >= 7


def test_griffe_extension_rewrites_colon_entries_for_the_numpy_parser(built_site):
    """docs/griffe_sections.py: ``name: what`` entries become NumPy entries,
    a section's closing paragraph becomes Notes, roles become code; in the
    built page a description sits in the description column."""
    sys.path.insert(0, str(DOCS))
    try:
        from griffe_sections import rewrite
    finally:
        sys.path.remove(str(DOCS))
    text = ("Do it.\n\nParameters\n----------\nmesh: the :class:`~bemcontact.mesh.SurfaceMesh`.\n"
            "size, order: two numbers,\n    on two lines.\n\nRegions: xmin, xmax.\n")
    assert rewrite(text) == (
        "Do it.\n\nParameters\n----------\nmesh\n    the `SurfaceMesh`.\nsize, order\n"
        "    two numbers,\n    on two lines.\n\nNotes\n-----\nRegions: xmin, xmax.\n")
    page = (built_site / "api.html").read_text(encoding="utf-8")
    row = re.search(r'title="bemcontact\.problemfile\.reader\.ProblemFile\.path">path</span>'
                    r'.*?doc-md-description">(.*?)</div>', page, flags=re.S)
    assert row and "the problem file." in row.group(1), row and row.group(1)
    assert ":class:" not in page
