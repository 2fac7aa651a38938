#!/usr/bin/python3
"""Write tests/decks/malformed/*.k: small decks, each with one input error.

Each deck starts with '$ expect:' lines: text that xdyna's error message must
contain (file:line, keyword, card, field, offending text). Rerun after
changing a case; the test runner reads the expectations from the files.
"""
import os

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "malformed")

NODES = [(1, 0, 0, 0), (2, 1, 0, 0), (3, 1, 1, 0), (4, 0, 1, 0),
         (5, 0, 0, 1), (6, 1, 0, 1), (7, 1, 1, 1), (8, 0, 1, 1)]


def base():
    lines = ["*KEYWORD", "*TITLE", "one hexahedron", "*CONTROL_TERMINATION", "   1.0e-05",
             "*DATABASE_GLSTAT", "   1.0e-06",
             "*MAT_ELASTIC", "$#     mid        ro         e        pr",
             "         1    7850.0   2.0e+11       0.3",
             "*SECTION_SOLID", "         1         1",
             "*PART", "block", "         1         1         1",
             "*NODE"]
    for n, x, y, z in NODES:
        lines.append(f"{n:8d}{x:16.1f}{y:16.1f}{z:16.1f}{0:8d}{0:8d}")
    lines += ["*ELEMENT_SOLID", "       1       1       1       2       3       4       5       6       7       8"]
    return lines


def at(lines, prefix):
    """1-based line number (after the expect header) of the first line starting with prefix."""
    for i, l in enumerate(lines):
        if l.startswith(prefix):
            return i + 1
    raise KeyError(prefix)


def case(name, mutate, *expect):
    lines = base()
    extra = mutate(lines) or {}
    header = [f"$ expect: {e.format(**extra)}" for e in expect]
    lines = header + lines
    # line numbers in expectations were computed without the header
    text = "\n".join(lines) + "\n*END\n"
    text = text.replace("@LINE@", "")
    with open(os.path.join(HERE, name + ".k"), "w") as f:
        f.write(text)


def replace(lines, prefix, new):
    i = at(lines, prefix) - 1
    lines[i] = new
    return i + 1


def main():
    os.makedirs(HERE, exist_ok=True)
    for f in os.listdir(HERE):
        if f.endswith(".k"):
            os.remove(os.path.join(HERE, f))
    nh = 0  # header lines are added in front: offsets below add the count of expect lines

    def mk(name, fn, *expect):
        def mut(lines):
            ln = fn(lines)
            return {"line": (ln or 0) + len(expect)}
        case(name, mut, *expect)

    mk("bad_number", lambda L: replace(L, "         1    7850.0", "         1    O.78e4   2.0e+11       0.3"),
       "bad_number.k:{line}: *MAT_ELASTIC card 1 field RO: 'O.78e4' is not a number")
    mk("bad_integer", lambda L: replace(L, "         1         1         1", "         1       1.5         1"),
       "bad_integer.k:{line}: *PART card 2 field SECID: '1.5' is not an integer")
    mk("unknown_keyword", lambda L: L.insert(3, "*FOO_BAR") or 4,
       "unknown_keyword.k:{line}: *FOO_BAR is not a supported keyword")
    mk("planned_keyword", lambda L: L.insert(3, "*SET_SOLID_GENERAL") or 4,
       "planned_keyword.k:{line}: *SET_SOLID_GENERAL is not implemented")
    mk("contact_bad_sstyp", lambda L: (L.insert(3, "*CONTACT_AUTOMATIC_SINGLE_SURFACE"),
                                       L.insert(4, "         1         0         9")) and 5,
       "contact_bad_sstyp.k:{line}: *CONTACT_AUTOMATIC_SINGLE_SURFACE card 1 field SSTYP: SSTYP 9 is not 0-6")
    mk("contact_undefined_part_set", lambda L: (L.insert(3, "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_ID"),
                                                L.insert(4, "        12 front"),
                                                L.insert(5, "         7         1         2         3")) and 6,
       "contact_undefined_part_set.k:{line}: *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE field SSID: part set 7 is not defined")
    mk("contact_master_node_set", lambda L: (L.insert(3, "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"),
                                             L.insert(4, "         1         1         3         4")) and 5,
       "contact_master_node_set.k:{line}: *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE card 1 field MSTYP: the master "
       "side is made of segments")
    mk("contact_bad_search", lambda L: (L.insert(3, "*CONTROL_XDYNA_CONTACT"), L.insert(4, "         3")) and 5,
       "contact_bad_search.k:{line}: *CONTROL_XDYNA_CONTACT card 1 field SEARCH: SEARCH 3 is not 0")
    mk("contact_bad_mnl", lambda L: (L.insert(3, "*CONTROL_XDYNA_CONTACT"), L.insert(4, "         1        10         2")) and 5,
       "contact_bad_mnl.k:{line}: *CONTROL_XDYNA_CONTACT card 1 field MNL: MNL 2 is not 0")
    mk("contact_segment_not_a_face", lambda L: (L.insert(3, "*SET_SEGMENT"), L.insert(4, "         4"),
                                                L.insert(5, "         1         2         7         8"),
                                                L.insert(6, "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"),
                                                L.insert(7, "         4         1         0         3")) and 8,
       "contact_segment_not_a_face.k:{line}: *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE 1 field SSID: segment 1 of *SET_SEGMENT 4 (nodes 1 2 7 8) is not an exterior element face")
    mk("undefined_node", lambda L: replace(L, "       1       1       1       2",
                                           "       1       1       1       2       3       4       5       6      99       8"),
       "undefined_node.k:{line}: *ELEMENT_SOLID 1 field N7: node 99 is not defined")
    mk("undefined_part", lambda L: replace(L, "       1       1       1       2",
                                           "       1       5       1       2       3       4       5       6       7       8"),
       "undefined_part.k:{line}: *ELEMENT_SOLID 1 field PID: part 5 is not defined")
    mk("undefined_material", lambda L: replace(L, "         1         1         1", "         1         1         7"),
       "undefined_material.k:{line}: *PART 1 field MID: material 7 is not defined")
    mk("undefined_section", lambda L: replace(L, "         1         1         1", "         1         3         1"),
       "undefined_section.k:{line}: *PART 1 field SECID: section 3 is not defined")
    mk("duplicate_node", lambda L: L.insert(at(L, "       8 "), f"{3:8d}{5.0:16.1f}{0.0:16.1f}{0.0:16.1f}") or
       at(L, "       8 ") + 1, "duplicate_node.k:{line}: *NODE 3 is defined twice")
    mk("duplicate_element", lambda L: L.append(L[-1]) or len(L),
       "duplicate_element.k:{line}: *ELEMENT_SOLID 1 is defined twice")
    mk("inverted_hex", lambda L: replace(L, "       1       1       1       2",
                                         "       1       1       1       4       3       2       5       8       7       6"),
       "inverted_hex.k:{line}: *ELEMENT_SOLID 1 is inverted")
    mk("degenerate_hex", lambda L: replace(L, "       1       1       1       2",
                                           "       1       1       1       1       3       4       5       6       7       8"),
       "degenerate_hex.k:{line}: *ELEMENT_SOLID 1 is degenerate")
    mk("negative_density", lambda L: replace(L, "         1    7850.0", "         1   -7850.0   2.0e+11       0.3"),
       "negative_density.k:{line}: *MAT_ELASTIC card 1 field RO: density must be positive")
    mk("zero_modulus", lambda L: replace(L, "         1    7850.0", "         1    7850.0       0.0       0.3"),
       "zero_modulus.k:{line}: *MAT_ELASTIC card 1 field E: Young's modulus must be positive")
    mk("bad_poisson", lambda L: replace(L, "         1    7850.0", "         1    7850.0   2.0e+11       0.5"),
       "bad_poisson.k:{line}: *MAT_ELASTIC card 1 field PR: Poisson's ratio must lie in (-1, 0.5)")
    mk("undefined_parameter", lambda L: replace(L, "         1    7850.0", "         1      &RHO   2.0e+11       0.3"),
       "undefined_parameter.k:{line}: *MAT_ELASTIC card 1 field RO: parameter 'RHO' is not defined")
    mk("missing_include", lambda L: (L.insert(3, "*INCLUDE"), L.insert(4, "no_such_file.k")) and 5,
       "missing_include.k:{line}: *INCLUDE: cannot open 'no_such_file.k'")
    mk("undefined_set", lambda L: (L.insert(3, "*BOUNDARY_SPC_SET"), L.insert(4, "         9         0         1")) and 5,
       "undefined_set.k:{line}: *BOUNDARY_SPC_SET field NSID: node set 9 is not defined")
    mk("bad_constraint_code", lambda L: replace(L, "       8 ", f"{8:8d}{0.0:16.1f}{1.0:16.1f}{1.0:16.1f}{9:8d}{0:8d}"),
       "bad_constraint_code.k:{line}: *NODE card 1 field TC: constraint code 9 is not 0-7")
    mk("no_termination", lambda L: (L.pop(3), L.pop(3)) and 0,
       "*CONTROL_TERMINATION with ENDTIM > 0 (or ENDCYC > 0) is required")
    mk("bad_elform", lambda L: replace(L, "         1         1\n", "") if False else
       replace(L, "         1         1", "         1         2"),
       "bad_elform.k:{line}: *SECTION_SOLID card 1 field ELFORM: solid formulation 2 is not supported")
    mk("too_many_free_fields", lambda L: replace(L, "         1    7850.0", "1, 7850.0, 2.0e11, 0.3, 0, 0, 0, 9"),
       "too_many_free_fields.k:{line}: *MAT_ELASTIC card 1 field 8: more fields than the card has (7)")
    mk("bad_hourglass_type", lambda L: (L.insert(3, "*HOURGLASS"), L.insert(4, "         1         9")) and 5,
       "bad_hourglass_type.k:{line}: *HOURGLASS card 1 field IHQ: IHQ 9 is not supported")
    mk("extra_card", lambda L: L.insert(at(L, "         1    7850.0"), "         5         5") or
       at(L, "         1    7850.0") + 1,
       "extra_card.k:{line}: *MAT_ELASTIC card 2: unexpected card")
    mk("bad_termination_time", lambda L: replace(L, "   1.0e-05", "     1.0ee"),
       "bad_termination_time.k:{line}: *CONTROL_TERMINATION card 1 field ENDTIM: '1.0ee' is not a number")
    mk("curve_not_increasing", lambda L: (L.insert(3, "*DEFINE_CURVE"), L.insert(4, "         3"),
                                          L.insert(5, f"{1.0:20.6e}{0.0:20.6e}"),
                                          L.insert(6, f"{0.5:20.6e}{1.0:20.6e}")) and 7,
       "curve_not_increasing.k:{line}: *DEFINE_CURVE card 2 field A: abscissae must increase")
    mk("undefined_curve", lambda L: (L.insert(3, "*LOAD_BODY_Z"), L.insert(4, "         4")) and 5,
       "undefined_curve.k:{line}: *LOAD_BODY_Z field LCID: curve 4 is not defined")
    mk("wall_without_normal", lambda L: (L.insert(3, "*RIGIDWALL_PLANAR"), L.insert(4, "         0"),
                                         L.insert(5, "       1.0       1.0       1.0       1.0       1.0       1.0")) and 6,
       "wall_without_normal.k:{line}: *RIGIDWALL_PLANAR card 2 field XH: the head point equals the tail")
    mk("rigid_without_dtinit", lambda L: replace(L, "*MAT_ELASTIC", "*MAT_RIGID") and 0,
       "*CONTROL_TIMESTEP field DTINIT: a model of rigid bodies alone has no element time step")
    mk("undefined_segment_set", lambda L: (L.insert(3, "*DEFINE_CURVE"), L.insert(4, "         3"),
                                           L.insert(5, f"{0.0:20.6e}{1.0:20.6e}"), L.insert(6, "*LOAD_SEGMENT_SET"),
                                           L.insert(7, "         8         3")) and 8,
       "undefined_segment_set.k:{line}: *LOAD_SEGMENT_SET field SSID: segment set 8 is not defined")
    mk("bad_shell_formulation", lambda L: (L.insert(3, "*SECTION_SHELL"), L.insert(4, "         2        16"),
                                           L.insert(5, "     0.002")) and 5,
       "bad_shell_formulation.k:{line}: *SECTION_SHELL card 1 field ELFORM: shell formulation 16 is not supported")
    print(f"wrote {len(os.listdir(HERE))} decks to {HERE}")


if __name__ == "__main__":
    main()
