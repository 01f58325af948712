#!/usr/bin/env python3
"""Writes the non-ASCII family of the scene corpus into tests/fuzz/corpus/scene/.

toml++ 3.3 asks of a character beyond ASCII outside strings and comments whether it is Unicode
whitespace, and for whole ranges of code points that question is undefined behaviour
(codegen/nhc/scene/toml_text_check.hpp). Each file is one small scene with one character of one
class of code points at one place: after a value, a key, a bracket, inside a bare value that holds
a quote (0"…", the shape the fuzzer found), after a backslash in a multi-line string (all refused
at their line and column), and inside strings and comments (accepted). Run it again after changing
the lists; the files are committed so that the fuzzers and faults:fuzz_corpus replay them.
Usage: tests/fuzz/non_ascii_family.py [DIR]
"""
import pathlib
import sys

# One code point per class of toml++ 3.3's is_non_ascii_horizontal_whitespace (its table splits
# U+00A0…U+FEFF into blocks of 0x3FA): C1 controls and NEL (vertical whitespace), NBSP, the block
# U+00A1…U+0499 (undefined), the Ogham space mark, the U+2000 spaces, the line separator, the blocks
# U+2C5E…U+2FFF and U+3001…U+3057 (undefined; the ideographic space U+3000 between them is not),
# the block U+FB26…U+FEFE (undefined), the byte order mark, and code points beyond it (three and
# four bytes): the first and last of each undefined block.
CODE_POINTS = [0x85, 0xA0, 0xA1, 0x27E, 0x3BB, 0x499, 0x1680, 0x2000, 0x2028, 0x2C5E, 0x3000, 0x3001,
               0x3057, 0xFB26, 0xFEFE, 0xFEFF, 0xFF21, 0x1F600]

HEAD = 'name = "non_ascii"\ncoordinates = ["x"]\nlagrangian = "x\'^2/2 - k*x^2/2"\n[parameters]\nk = 1.0\n'

# (name, the text after HEAD with {c} for the character, refused?)
PLACES = [
    ("after_number", "c = 1{c}\n", True),
    ("after_quote_in_number", 'c = 0"t{c}"\n', True),
    ("after_string", 'c = "1"{c}\n', True),
    ("after_boolean", "c = true{c}\n", True),
    ("after_key", "c{c} = 1\n", True),
    ("after_dot_in_key", "c.{c} = 1\n", True),
    ("after_header_bracket", "[{c}]\n", True),
    ("after_header", "[initial]{c}\n", True),
    ("after_array_bracket", "c = [{c}]\n", True),
    ("after_array_comma", "c = [1,{c}]\n", True),
    ("after_brace", "c = {{{c}}}\n", True),
    ("after_backslash", 'c = """\\{c}"""\n', True),
    ("after_line_ending_backslash", 'c = """\\\n  {c}"""\n', True),
    ("in_comment", "# {c}\n", False),
    ("in_string", 'c = "1{c}"\n', False),
    ("in_literal_string", "c = '1{c}'\n", False),
    ("in_multiline_string", 'c = """\n1{c}"""\n', False),
    ("in_multiline_literal", "c = '''1{c}'''\n", False),
]


def main():
    root = pathlib.Path(__file__).resolve().parent
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else root / "corpus" / "scene"
    out.mkdir(parents=True, exist_ok=True)
    for place, text, _ in PLACES:
        for cp in CODE_POINTS:
            path = out / f"non_ascii_{place}_U{cp:04X}.toml"
            path.write_bytes((HEAD + text.format(c=chr(cp))).encode("utf-8"))


if __name__ == "__main__":
    main()
