"""Regenerate docs/model-file.md from docs/model-file.md.in and the model-file schema."""

from pathlib import Path

from pfeie.io import reference_markdown

here = Path(__file__).resolve().parent
text = (here / "model-file.md.in").read_text().replace("@TABLE@", reference_markdown())
(here / "model-file.md").write_text(text)
