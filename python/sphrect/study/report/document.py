"""The report's document: the same content built as Markdown and as HTML."""
from __future__ import annotations

import html
from typing import Sequence


class Document:
    """Builds the same content as Markdown and as HTML."""

    def __init__(self):
        self.md, self.html = [], []

    def heading(self, text: str, level: int = 2):
        self.md.append("#" * level + " " + text + "\n")
        self.html.append(f"<h{level}>{html.escape(text)}</h{level}>")

    def para(self, text: str):
        self.md.append(text + "\n")
        body = html.escape(text)
        while "**" in body:  # the only Markdown emphasis we use
            body = body.replace("**", "<b>", 1).replace("**", "</b>", 1)
        if body.startswith("- "):
            body = "&bull; " + body[2:]
        self.html.append(f"<p>{body}</p>")

    def table(self, header: Sequence[str], rows: Sequence[Sequence[str]]):
        if not rows:
            return
        self.md.append("| " + " | ".join(header) + " |")
        self.md.append("|" + "|".join("---" for _ in header) + "|")
        for r in rows:
            self.md.append("| " + " | ".join(str(c) for c in r) + " |")
        self.md.append("")
        head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>" for r in rows)
        self.html.append(f"<table><tr>{head}</tr>{body}</table>")

    def image(self, path: str, caption: str):
        self.md.append(f"![{caption}]({path})\n")
        self.html.append(f'<figure><img src="{html.escape(path)}" alt="{html.escape(caption)}">'
                         f"<figcaption>{html.escape(caption)}</figcaption></figure>")

    def markdown(self) -> str:
        return "\n".join(self.md) + "\n"

    def to_html(self, title: str) -> str:
        style = ("body{font-family:sans-serif;max-width:1300px;margin:2em auto;padding:0 1em}"
                 "table{border-collapse:collapse;margin:1em 0;font-size:90%}td,th{border:1px solid #ccc;"
                 "padding:3px 8px;text-align:right}img{max-width:100%}figcaption{color:#555;font-size:90%}")
        return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
                f"<style>{style}</style></head><body>" + "\n".join(self.html) + "</body></html>\n")
