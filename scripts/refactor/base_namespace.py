#!/usr/bin/env python3
"""base/ gets its own include path and namespace: base/nhc/runtime/* and base/nhc/{clock,primed_name}.hpp
move to base/nhc/base/, namespace nhc::runtime (and nhc, for the clock and primed_name) of those files
becomes nhc::base, and every use in the tree follows: include paths, `runtime::X` -> `base::X`, and an
unqualified X (as code in namespace nhc::runtime, or in nhc, wrote it) -> `base::X` (`nhc::base::X`
in a file outside namespace nhc).

Run from the repository's root on a clean checkout: `python3 scripts/refactor/base_namespace.py`
(`--no-move` when the files are already under base/nhc/base/, e.g. on a branch merged after the
move: it then only rewrites the uses). It is idempotent: a second run changes nothing."""
import os
import re
import subprocess
import sys

MOVED = ['constraint_solver.hpp', 'constraint_solver.cpp', 'errors.hpp', 'errors.cpp', 'initial_point.hpp',
         'initial_point.cpp', 'number_text.hpp']
MOVED_TOP = ['clock.hpp', 'primed_name.hpp']  # were base/nhc/*.hpp in namespace nhc
# Every name the moved headers declare at namespace scope.
SYMBOLS = ['FailureKind', 'ModelError', 'SolverError', 'kNoTime', 'SparseEntry', 'kSparseStepSize',
           'ConstraintFunctions', 'ConstraintSolveStatus', 'ConstraintSolveResult', 'solve_constraints',
           'InitialPointTolerance', 'initial_point_tolerance', 'solve_initial_point', 'InitialPointSolve',
           'solve_or_repair_initial_point', 'InvolvedValue', 'InconsistentInitialPoint', 'number_text',
           'shortest_text', 'append_shortest', 'Clock', 'seconds_since', 'primed_name']
# Found by argument-dependent lookup when unqualified (their arguments are base's types); only the
# qualified spelling is rewritten.
QUALIFIED_ONLY = ['describe', 'to_string']
SOURCE = ('.cpp', '.hpp', '.h', '.cc', '.in')
TEXT = SOURCE + ('.md', '.txt', '.cmake', '.py', '.sh', '.pyi')


def git(*args):
    return subprocess.run(['git', *args], check=True, capture_output=True, text=True).stdout


def move():
    os.makedirs('base/nhc/base', exist_ok=True)
    for f in MOVED:
        if os.path.exists('base/nhc/runtime/' + f):
            git('mv', 'base/nhc/runtime/' + f, 'base/nhc/base/' + f)
    for f in MOVED_TOP:
        if os.path.exists('base/nhc/' + f):
            git('mv', 'base/nhc/' + f, 'base/nhc/base/' + f)


def rewrite_paths(text):
    names = '|'.join(re.escape(f) for f in MOVED)
    text = re.sub(r'base/nhc/runtime/(' + names + r')', r'base/nhc/base/\1', text)
    text = re.sub(r'(?<![\w/])nhc/runtime/(' + names + r')', r'nhc/base/\1', text)
    text = re.sub(r'base/nhc/runtime/\*', 'base/nhc/base/*', text)
    text = re.sub(r'base/nhc/runtime/constraint_solver\.\*', 'base/nhc/base/constraint_solver.*', text)
    top = '|'.join(re.escape(f) for f in MOVED_TOP)
    text = re.sub(r'base/nhc/(' + top + r')', r'base/nhc/base/\1', text)
    text = re.sub(r'(?<![\w/])nhc/(' + top + r')', r'nhc/base/\1', text)
    return text


def rewrite_base_file(path, text):
    text = text.replace('namespace nhc::runtime {', 'namespace nhc::base {')
    text = text.replace('}  // namespace nhc::runtime', '}  // namespace nhc::base')
    if os.path.basename(path) in MOVED_TOP:
        text = re.sub(r'^namespace nhc \{$', 'namespace nhc::base {', text, flags=re.M)
        text = re.sub(r'^\}  // namespace nhc$', '}  // namespace nhc::base', text, flags=re.M)
    return text


QUALIFIED = re.compile(r'\bruntime::(' + '|'.join(SYMBOLS + QUALIFIED_ONLY) + r')\b')


def code_part(line):
    """The line's code before a // comment (a // inside a string literal ends it too early, which
    only leaves code alone)."""
    stripped = line.lstrip()
    if stripped.startswith('//') or stripped.startswith('*') or stripped.startswith('/*'):
        return '', line
    cut = line.find('//')
    if cut < 0:
        return line, ''
    return line[:cut], line[cut:]


def rewrite_uses(path, text):
    text = QUALIFIED.sub(r'base::\1', text)
    if path.startswith('base/') or not path.endswith(SOURCE):
        return text
    in_nhc = re.search(r'^\s*namespace nhc\b', text, flags=re.M) or 'using namespace nhc;' in text
    prefix = 'base::' if in_nhc else 'nhc::base::'
    # names the file defines itself (a local `using Clock = …`, its own function) keep their spelling
    # (a .cpp file's own header counts: progress_bar.hpp's member `using Clock = …`)
    own = text
    header = os.path.splitext(path)[0] + '.hpp'
    if path.endswith('.cpp') and os.path.isfile(header):
        with open(header, encoding='utf-8', errors='surrogateescape') as f:
            own += '\n' + f.read()
    local = {name for name in SYMBOLS
             if re.search(r'(using\s+' + name + r'\s*=|\b(struct|class|enum class|enum)\s+' + name + r'\b|'
                          r'^(?:static\s+|inline\s+)?[\w:<>]+[\s\*&]+' + name + r'\()', own, flags=re.M)}
    pattern = re.compile(r'(?<![\w:.>$])(' + '|'.join(n for n in SYMBOLS if n not in local) +
                         r')\b(?!\s*=[^=])') if len(local) < len(SYMBOLS) else None
    out = []
    in_string_block = False
    for line in text.split('\n'):
        if line.lstrip().startswith('#') or 'R"' in line or in_string_block:
            # preprocessor lines, raw strings (generated code, TOML) stay as written
            if 'R"' in line and ')' + line.split('R"', 1)[1].split('(', 1)[0] + '"' not in line:
                in_string_block = True
            elif in_string_block and re.search(r'\)\w*"', line):
                in_string_block = False
            out.append(line)
            continue
        code, comment = code_part(line)
        # strings in the code part stay as written
        pieces = re.split(r'("(?:[^"\\]|\\.)*")', code)
        for k in range(0, len(pieces), 2):
            if re.match(r'\s*using\s+(' + '|'.join(SYMBOLS) + r')\s*=', pieces[k]):
                continue
            if pattern:
                pieces[k] = pattern.sub(lambda m: prefix + m.group(1), pieces[k])
        out.append(''.join(pieces) + comment)
    return '\n'.join(out)


def main():
    if '--no-move' not in sys.argv:
        move()
    for path in git('ls-files').split('\n'):
        if not path or not path.endswith(TEXT) or path.startswith(('generated/', 'scripts/refactor/')):
            continue
        if not os.path.isfile(path):
            continue
        with open(path, encoding='utf-8', errors='surrogateescape') as f:
            text = f.read()
        new = rewrite_paths(text)
        if path.startswith('base/nhc/base/'):
            new = rewrite_base_file(path, new)
        new = rewrite_uses(path, new)
        if new != text:
            with open(path, 'w', encoding='utf-8', errors='surrogateescape') as f:
                f.write(new)


if __name__ == '__main__':
    main()
