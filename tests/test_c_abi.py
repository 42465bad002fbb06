"""fricgen.control.c_abi against c_runtime/fric_ctrl.h: enums, struct layout, and the two
parameter paths derived from the table (cffi and the firmware's C initializer)."""
import re
import shutil
import subprocess

import pytest

from fricgen.codegen.cbuild import CFLAGS, STRICT_WARNINGS
from fricgen.codegen.render import controller_files
from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.c_abi import ENUMS, FLAGS, STRUCTS, VERSION, params_initializer
from fricgen.control.c_controller import CController, build_controller

CC = shutil.which("cc") or shutil.which("gcc")
pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler")

SETTINGS = AdaptiveBackstepping(law="a", friction_input="vd", gamma=[[2.0, 0.5], [0.5, 3.0]],
                                k1=50.0, k2=12.5, delta=0.01, ts=2e-3, phi_n=18.0, i_max=7.5,
                                a0=(0.2, 0.9))


def run_c(tmp_path, main_body: str, prelude: str = "", flags=()) -> str:
    """Compile a program that includes fric_ctrl.h with the strict flags (and ``flags``), run
    it, return stdout."""
    for name, text in controller_files().items():
        (tmp_path / name).write_text(text)
    src = tmp_path / "probe.c"
    src.write_text(f'#include <stddef.h>\n#include <stdio.h>\n#include "fric_ctrl.h"\n{prelude}\n'
                   f"int main(void)\n{{\n{main_body}    return 0;\n}}\n")
    exe = tmp_path / "probe"
    build = subprocess.run([CC, *CFLAGS, *STRICT_WARNINGS, *flags, str(src), "-o", str(exe)],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    return subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout


def test_header_declares_the_tables_enums_and_choices_with_their_members_in_order():
    header = controller_files()["fric_ctrl.h"]
    enums = [(ctype, re.findall(r"^\s*(FRIC_CTRL_\w+)", body, re.M))
             for body, ctype in re.findall(r"typedef enum \{(.*?)\} (\w+);", header, re.S)]
    choices = [(ctype, re.findall(rf"^#define (FRIC_CTRL_\w+) \(\({ctype}\)\d+\)$", header, re.M))
               for ctype in re.findall(r"^typedef int32_t (\w+);", header, re.M)]
    assert enums + choices == [(e.ctype, [m.name for m in e.members]) for e in ENUMS]


def test_header_values_field_types_and_field_order_agree_with_the_table(tmp_path):
    checks, prints = [], ['    printf("FRIC_CTRL_VERSION %d\\n", FRIC_CTRL_VERSION);\n']
    for enum in ENUMS + (FLAGS,):
        prints += [f'    printf("{m.name} %d\\n", (int){m.name});\n' for m in enum.members]
    # the cffi declarations (FLAGS.cdef) say unsigned int
    prints.append(f'    printf("{FLAGS.ctype} %d\\n", (int)(sizeof({FLAGS.ctype}) == sizeof(unsigned)));\n')
    for ctype, fields in STRUCTS.items():
        # each field's C type must be the table's: a pointer of the other type would not compile
        checks.append(f"void check_{ctype}(const {ctype} *s)\n{{\n")
        for f in fields:
            declarator = f"(*{f.name})[{f.length}]" if f.length else f"*{f.name}"
            checks.append(f"    const {f.ctype} {declarator} = &s->{f.name};\n    (void){f.name};\n")
        checks.append("}\n")
        prints.append(f'    printf("{ctype} %lu\\n", (unsigned long)sizeof({ctype}));\n')
        prints += [f'    printf("{ctype}.{f.name} %lu %lu\\n", '
                   f"(unsigned long)offsetof({ctype}, {f.name}), "
                   f"(unsigned long)sizeof((({ctype} *)0)->{f.name}));\n" for f in fields]
    out = dict(line.split(" ", 1) for line in run_c(tmp_path, "".join(prints),
                                                     "".join(checks)).splitlines())

    assert int(out["FRIC_CTRL_VERSION"]) == VERSION
    assert int(out[FLAGS.ctype]) == 1
    for enum in ENUMS + (FLAGS,):
        for m in enum.members:
            assert int(out[m.name]) == m.value, m.name
    for ctype, fields in STRUCTS.items():
        end = 0
        for f in fields:  # the table's fields, back to back in its order, fill the struct
            offset, size = (int(w) for w in out[f"{ctype}.{f.name}"].split())
            assert offset == end, f"{ctype}.{f.name}"
            end += size
        assert int(out[ctype]) == end, ctype


def test_the_structs_keep_their_layout_under_short_enums(tmp_path):
    """arm-none-eabi-gcc makes enums as small as they fit (-fshort-enums): the structs' fields that
    hold an enumerator are int32_t, so a runtime and a caller built with either setting agree."""
    prints = "".join(f'    printf("{ctype} %lu %lu\\n", (unsigned long)sizeof({ctype}), '
                     f"(unsigned long)offsetof({ctype}, {field}));\n"
                     for ctype, field in (("fric_ctrl_params_t", "friction_at"),
                                          ("fric_ctrl_t", "flags")))
    layouts = [run_c(tmp_path, prints, flags=flags) for flags in ((), ("-fshort-enums",))]
    assert layouts[0] == layouts[1] and layouts[0].count("\n") == 2
    short = run_c(tmp_path, '    printf("%lu\\n", (unsigned long)sizeof(fric_ctrl_status_t));\n',
                  flags=("-fshort-enums",))
    assert short.strip() == "1"                   # the flag does shrink an enum (the status codes)


def test_firmware_initializer_and_cffi_parameters_are_the_same_struct(tmp_path):
    module = build_controller()
    from_cffi = bytes(module.ffi.buffer(CController(module, SETTINGS).params())).hex()
    prelude = f"static const fric_ctrl_params_t params = {params_initializer(SETTINGS)};\n"
    body = ("    size_t k;\n"
            "    for (k = 0; k < sizeof params; ++k) {\n"
            '        printf("%02x", ((const unsigned char *)&params)[k]);\n'
            "    }\n")
    assert run_c(tmp_path, body, prelude) == from_cffi


def test_cffi_declares_every_function_the_header_prototypes():
    from fricgen.control.c_abi import function_declarations
    names = re.findall(r"(fric_ctrl_\w+)\(", function_declarations())
    assert names == ["fric_ctrl_default_params", "fric_ctrl_init", "fric_ctrl_step",
                     "fric_ctrl_friction_velocity", "fric_ctrl_step_fn", "fric_ctrl_step_sample"]
