"""Pygments lexers for the languages the docs tag their code blocks with (tests/python/test_docs.py):
``lammps`` (a complete deck, run by the docs test), ``lammps-fragment`` (lines of a deck, not run),
``mbdyn`` (MBDyn input)."""
from pygments.lexer import RegexLexer, bygroups
from pygments.token import Comment, Keyword, Name, Number, String, Text


class LammpsLexer(RegexLexer):
    name = "LAMMPS"
    aliases = ["lammps", "lammps-fragment"]
    tokens = {
        "root": [
            (r"#.*$", Comment.Single),
            (r"^(\s*)([a-z_/]+)", bygroups(Text, Keyword)),
            (r"\$\{[^}]*\}|\$[a-zA-Z]|v_\w+|c_\w+(\[[^\]]*\])?|f_\w+(\[[^\]]*\])?", Name.Variable),
            (r'"[^"]*"', String),
            (r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\b", Number),
            (r"\s+", Text),
            (r"\S+", Text),
        ]
    }


class MbdynLexer(RegexLexer):
    name = "MBDyn"
    aliases = ["mbdyn"]
    tokens = {"root": [(r"#.*$", Comment.Single), (r'"[^"]*"', String),
                       (r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\b", Number), (r"\s+", Text), (r"[^\s\"#]+", Text)]}


def setup(app):
    app.add_lexer("lammps", LammpsLexer)
    app.add_lexer("lammps-fragment", LammpsLexer)
    app.add_lexer("mbdyn", MbdynLexer)
    return {"parallel_read_safe": True}
