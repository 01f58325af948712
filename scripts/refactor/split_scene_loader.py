#!/usr/bin/env python3
"""Splits codegen/nhc/scene/scene_loader.cpp by part: the SceneReader's members move out of the
class, unchanged but for their first line (SceneReader:: before the name, no `static`), into one
file per part; the class is declared in scene_reader.hpp. Run from the repository's root."""
import re, sys

D = 'codegen/nhc/scene/'
src = open(D + 'scene_loader.cpp').read()
lines = src.split('\n')

def find(pred, start=0):
    for i in range(start, len(lines)):
        if pred(lines[i]):
            return i
    raise SystemExit('not found')

# --- the include block and the regions outside the class -------------------------------------
ns_open = find(lambda l: l == 'namespace nhc {')
includes = lines[:ns_open]
scene_start = ns_open + 1
pr_start = find(lambda l: l == 'namespace scene_reading {')
anon = find(lambda l: l == 'namespace {', pr_start)
anon_end_region = find(lambda l: l.startswith('class SceneReader {'), anon)
cls_start = anon_end_region
cls_end = find(lambda l: l == '};', cls_start)
after_cls = find(lambda l: l == '}  // namespace', cls_end)
parse_start = find(lambda l: l.startswith('Scene parse_scene('), after_cls)
text_start = find(lambda l: l.startswith('std::string switched_source('), parse_start)
load_start = find(lambda l: l.startswith('Scene load_scene('), text_start)
end_ns = max(i for i, l in enumerate(lines) if l == '}  // namespace nhc')

scene_part = lines[scene_start:pr_start]                         # Scene's own functions
printable_part = lines[pr_start + 1:find(lambda l: l == '}  // namespace scene_reading', pr_start)]
free_helpers = lines[find(lambda l: l.startswith('bool is_function_name'), anon):cls_start]
parse_part = lines[parse_start:text_start]
text_part = lines[text_start:load_start]
load_part = lines[load_start:end_ns]

# --- the class's members ----------------------------------------------------------------------
body = lines[cls_start + 1:cls_end]
members = []   # (name, doc lines, member lines)
inline = []    # lines kept in the class (access labels, one-liners, the constructor, data)
i = 0
doc = []
while i < len(body):
    l = body[i]
    if l.strip().startswith('///') or l.strip().startswith('// '):
        doc.append(l); i += 1; continue
    if l in (' public:', ' private:') or l.strip() == '':
        inline.extend(doc); doc = []; inline.append(l); i += 1; continue
    # a member starts here: its signature runs to the line ending in '{' (or a one-liner '}')
    j = i
    while not (body[j].rstrip().endswith('{') or body[j].rstrip().endswith('}') or body[j].rstrip().endswith(';')):
        j += 1
    sig = body[i:j + 1]
    joined = ' '.join(s.strip() for s in sig)
    if body[j].rstrip().endswith(';') or body[j].rstrip().endswith('}') or joined.startswith('SceneReader('):
        # data, a one-liner or the constructor: stays in the class
        k = j
        if joined.startswith('SceneReader('):
            while body[k] != '  }':
                k += 1
        inline.extend(doc); doc = []
        inline.extend(body[i:k + 1]); i = k + 1; continue
    k = j + 1
    while body[k] != '  }':
        k += 1
    name = re.search(r'([A-Za-z_][A-Za-z0-9_]*)\(', joined.replace('template <class Names>', '')).group(1)
    members.append((name, doc, sig, body[j + 1:k + 1]))
    inline_decl = [s for s in sig]
    # the declaration: the signature up to '{', with ';'
    decl = '\n'.join(sig)
    decl = decl[:decl.rstrip().rfind('{')].rstrip() + ';'
    inline.append(decl)
    doc = []
    i = k + 1

def dedent(ls):
    return [l[2:] if l.startswith('  ') else l for l in ls]

def definition(name, doc, sig, rest):
    s = dedent(sig)
    text = '\n'.join(s)
    text = text.replace('[[noreturn]] ', '')
    text = re.sub(r'^(template <class Names>\n)?static ', r'\1', text)
    text = text.replace(name + '(', 'SceneReader::' + name + '(', 1)
    return '\n'.join(dedent(doc)) + ('\n' if doc else '') + text + '\n' + '\n'.join(dedent(rest)) + '\n'

PARTS = {
    'scene_reader.cpp': ['at', 'fail', 'shortest', 'check_keys', 'require', 'string_value', 'array_value',
                         'table_value', 'number_value', 'type_name', 'check_variable_name', 'check_variable_name_at',
                         'expression_location', 'expression', 'is_zero_at', 'multipliers_allowed',
                         'entries_in_file_order', 'read_quantities', 'constant_value', 'number_expression'],
    'scene_loader.cpp': ['read'],
    'scene_system_reader.cpp': ['read_definitions', 'read_reference', 'read_input_signals', 'read_forces',
                                'names_among', 'names_any_of', 'derived_parameter', 'read_derived_parameters'],
    'scene_experiment_reader.cpp': ['read_initial', 'check_fixed', 'read_simulate', 'initial_point_of',
                                    'read_events', 'read_contacts', 'read_controller', 'read_mpc'],
    'scene_presentation_reader.cpp': ['read_outputs', 'value_at', 'read_visuals', 'check_visual_value',
                                      'color_value'],
}
where = {n: f for f, ns in PARTS.items() for n in ns}
for m in members:
    if m[0] not in where:
        raise SystemExit('unplaced member ' + m[0])

HEAD = {
    'scene_reader.cpp': '// What the parts of the scene reader share: locations, refusals, the checked values of a TOML\n// node, names, expressions (scene_reader.hpp).',
    'scene_loader.cpp': '// Reads scene TOML files (toml++) into Scene, validating every key and expression.\n// Each problem becomes an InputError with the file, line and column of the offending value.\n// The tables are read by part: scene_system_reader.cpp, scene_experiment_reader.cpp (and\n// scene_optimize_reader.cpp), scene_presentation_reader.cpp.',
    'scene_system_reader.cpp': '// The system\'s tables of a scene file: [parameters] computed from others, [definitions], [inputs],\n// [forces], [reference] (docs/architecture.md, "The scene\'s three parts").',
    'scene_experiment_reader.cpp': '// The experiment\'s tables of a scene file: [initial], [simulate], [events], [contacts],\n// [controller] (docs/architecture.md, "The scene\'s three parts").',
    'scene_presentation_reader.cpp': '// The presentation\'s tables of a scene file: [outputs], [visual] (docs/architecture.md, "The\n// scene\'s three parts").',
}
incl = [l for l in includes if l.startswith('#include') or l == '']
incl = [l for l in incl if 'scene_reader.hpp' not in l]
while incl and incl[0] == '':
    incl.pop(0)

def write(path, head, parts_text, ns='nhc::scene_reading', extra_before=''):
    out = head + '\n#include "nhc/scene/scene_reader.hpp"\n\n' + '\n'.join(incl).rstrip() + '\n\n'
    out += 'namespace ' + ns + ' {\n\n' + extra_before + parts_text.rstrip() + '\n\n}  // namespace ' + ns + '\n'
    open(D + path, 'w').write(out)

for f in PARTS:
    defs = '\n'.join(definition(*m) for m in members if where[m[0]] == f)
    if f == 'scene_reader.cpp':
        pre = '\n'.join(printable_part).strip() + '\n\n' + '\n'.join(free_helpers).strip() + '\n\n'
        write(f, HEAD[f], defs, extra_before=pre)
    elif f == 'scene_loader.cpp':
        tail = '\n'.join(parse_part).rstrip() + '\n\n' + '\n'.join(load_part).rstrip() + '\n'
        out = HEAD[f] + '\n#include "nhc/scene/scene_reader.hpp"\n\n' + '\n'.join(incl).rstrip() + '\n\n'
        out += 'namespace nhc {\n\nnamespace scene_reading {\n\n' + defs.rstrip() + '\n\n}  // namespace scene_reading\n\n'
        out += 'using scene_reading::SceneReader;\n\n' + tail + '\n}  // namespace nhc\n'
        open(D + f, 'w').write(out)
    else:
        write(f, HEAD[f], defs)

# Scene's own functions and the text rewrites
out = '// The Scene\'s own functions (scene.hpp): parameter values, inputs at a time, names.\n'
out += '#include <algorithm>\n#include <cctype>\n#include <cmath>\n#include <set>\n\n'
out += '#include "nhc/scene/constant_expression.hpp"\n#include "nhc/scene/scene.hpp"\n\nnamespace nhc {\n\n'
out += '\n'.join(scene_part).strip() + '\n\n}  // namespace nhc\n'
open(D + 'scene.cpp', 'w').write(out)
out = '// Scene texts rewritten (scene.hpp, scene_text.hpp): the system\'s text, a switched model\'s, the\n// [inputs] laws written in place.\n'
out += '#include "nhc/scene/scene_reader.hpp"\n\n' + '\n'.join(incl).rstrip() + '\n\nnamespace nhc {\n\n'
out += 'using scene_reading::looks_like_multiplier;\n\n' + '\n'.join(text_part).strip() + '\n\n}  // namespace nhc\n'
open(D + 'scene_text.cpp', 'w').write(out)

# The header: the class declaration, the member functions grouped by the file that defines them
hdr = open(D + 'scene_reader.hpp').read()
decls = {}
for name, doc, sig, rest in members:
    d = '\n'.join(sig)
    decls.setdefault(where[name], []).append(d[:d.rstrip().rfind('{')].rstrip() + ';')
c0 = next(i for i, l in enumerate(inline) if l.startswith('  SceneReader('))
c1 = inline.index('  }', c0)
ctor = inline[c0:c1 + 1]
rest_inline = [l for l in inline[:c0] + inline[c1 + 1:]
               if not (l.rstrip().endswith(';') and '(' in l) and l not in (' public:', ' private:')]
kept = ctor + rest_inline
ctor_end = len(ctor) - 1
data_start = next(i for i, l in enumerate(kept) if l.strip().startswith('const std::string& text_;'))
one_liners = [l for l in kept[ctor_end + 1:data_start] if l.strip()]
cls = ['/// Reads a scene file\'s text into a Scene: read() checks the text, parses it and reads the tables',
       '/// by part; each group of member functions below is defined in the file its comment names.',
       'class SceneReader {', ' public:'] + [l for l in kept[:ctor_end + 1] if l.strip()] + ['', '  Scene read();  // scene_loader.cpp', '', ' private:']
for f, title in [('scene_reader.cpp', 'what every part uses'), ('scene_system_reader.cpp', 'the system'),
                 ('scene_experiment_reader.cpp', 'the experiment'), ('scene_presentation_reader.cpp', 'the presentation')]:
    cls.append('  // ' + f + ': ' + title)
    if f == 'scene_reader.cpp':
        cls.extend(one_liners)
    cls.extend(decls[f])
    cls.append('')
cls += kept[data_start:] + ['};']
helpers_decl = '''bool is_function_name(const std::string& name);
/// lambda<N>: a multiplier's name.
bool looks_like_multiplier(const std::string& name);
/// name_d<N>: a jet variable's name.
bool has_jet_suffix(const std::string& name);

'''
hdr = hdr.replace('#include <string>\n\n#include "nhc/scene/scene.hpp"\n',
                  '#include <map>\n#include <optional>\n#include <set>\n#include <sstream>\n#include <string>\n'
                  '#include <utility>\n#include <vector>\n\n#include "nhc/scene/definition_table.hpp"\n'
                  '#include "nhc/scene/expression_parser.hpp"\n#include "nhc/scene/scene.hpp"\n'
                  '#include "nhc/scene/value.hpp"\n', 1)
hdr = hdr.replace('/// [optimize] of the scene', helpers_decl + '\n'.join(cls) + '\n\n/// [optimize] of the scene', 1)
open(D + 'scene_reader.hpp', 'w').write(hdr)
print('members moved:', len(members))
