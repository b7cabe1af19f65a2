"""The C API page (docs/c-api.md) names every public function of
csrc/include, as test_status holds the status registry to its mirror: a
function added to a header without a line on the page fails here.  The page
may group a family with braces (`sig_limit_{init,step}_{f,q}`)."""
import itertools
import re

from conftest import ROOT

DECLARATION = re.compile(r"^[ \t]*(?:static\s+)?(?:inline\s+)?(?:const\s+)?[A-Za-z_]\w*[\s*]+(sig_\w+)\s*\(",
                         re.MULTILINE)


def header_functions():
    """Every sig_* function declared or defined (static inline) in a public
    header; comments and preprocessor lines (macros) left out."""
    names = {}
    for header in sorted((ROOT / "csrc" / "include").glob("*.h")):
        text = re.sub(r"/\*.*?\*/", "", header.read_text(), flags=re.S)
        text = re.sub(r"//[^\n]*", "", text)
        text = re.sub(r"^[ \t]*#[^\n]*(?:\\\n[^\n]*)*", "", text, flags=re.M)
        for m in DECLARATION.finditer(text):
            names.setdefault(m.group(1), header.name)
    return names


def expand(token):
    """`sig_a_{x,y}_{f,q}` -> {sig_a_x_f, sig_a_x_q, sig_a_y_f, sig_a_y_q}."""
    parts = re.split(r"(\{[^}]*\})", token)
    options = [p[1:-1].split(",") if p.startswith("{") else [p] for p in parts]
    return {"".join(choice) for choice in itertools.product(*options)}


def page_names(text):
    names = set()
    for m in re.finditer(r"sig_[\w{},]*", text):
        names |= expand(m.group(0).rstrip(","))
    return names


def test_brace_groups_expand():
    assert expand("sig_limit_{init,step}_{f,q}") == {"sig_limit_init_f", "sig_limit_init_q",
                                                   "sig_limit_step_f", "sig_limit_step_q"}
    assert page_names("`sig_crc16_ccitt`, `sig_pwl_{init,eval}_q16`") == {
        "sig_crc16_ccitt", "sig_pwl_init_q16", "sig_pwl_eval_q16"}


def test_headers_are_read():
    found = header_functions()
    assert len(found) > 100
    assert found["sig_chain_step_q"] == "sig_chain.h"
    assert "sig_asr32" in found                 # static inline helpers count too


def test_every_public_function_is_on_the_c_api_page():
    page = page_names((ROOT / "docs" / "c-api.md").read_text())
    missing = sorted(f"{name} ({header})" for name, header in header_functions().items() if name not in page)
    assert missing == [], "docs/c-api.md does not name: " + ", ".join(missing)
