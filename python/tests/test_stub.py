"""The type stub (tristereo/_tristereo.pyi) against the module: the keywords
editors complete are exactly the ones the module takes, with the values the
table allows."""
import ast
import os

import tristereo

RUN_KEYWORDS = {"threads", "kernels", "cpus", "pin"}
ANNOTATION = {"int": "int", "decimal": "float", "size": "_Size", "flag": "bool"}


def stub_functions():
    path = os.path.join(os.path.dirname(tristereo.__file__), "_tristereo.pyi")
    assert os.path.isfile(path), f"no type stub beside the module: {path}"
    tree = ast.parse(open(path).read())
    funcs = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    funcs[f"{node.name}.{item.name}"] = item
        elif isinstance(node, ast.FunctionDef) and node.col_offset == 0:
            funcs[node.name] = node
    return tree, funcs


def aliases(tree):
    return {t.id: ast.unparse(node.value) for node in tree.body if isinstance(node, ast.Assign)
            for t in node.targets}


def check_keywords(func, tree, run):
    options = {o["keyword"]: o for o in tristereo.model_options() if o["keyword"] != "ndisp"}
    kwonly = {a.arg: ast.unparse(a.annotation) for a in func.args.kwonlyargs}
    assert set(kwonly) == set(options) | (RUN_KEYWORDS if run else set())
    assert "ndisp" in [a.arg for a in func.args.args]
    names = aliases(tree)
    for kw, o in options.items():
        annotation = names.get(kwonly[kw], kwonly[kw])
        if o["kind"] == "choice":
            assert annotation == "Literal[" + ", ".join(repr(c) for c in o["choices"]) + "]", (kw, annotation)
        else:
            assert kwonly[kw] == ANNOTATION[o["kind"]], (kw, kwonly[kw])


def test_stub_lists_every_keyword_of_pipeline_and_verify():
    tree, funcs = stub_functions()
    check_keywords(funcs["Pipeline.__init__"], tree, run=True)
    check_keywords(funcs["verify"], tree, run=False)


def test_stub_names_every_public_name_and_output_attribute():
    tree, funcs = stub_functions()
    classes = {n.name: n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)}
    defined = set(classes) | {n for n in funcs if "." not in n} | {
        t.target.id for t in tree.body if isinstance(t, ast.AnnAssign)}
    public = {n for n in dir(tristereo._tristereo) if not n.startswith("_")} | {"__version__"}
    assert public <= defined, public - defined
    out_attrs = {t.target.id for t in classes["Output"].body if isinstance(t, ast.AnnAssign)}
    assert out_attrs == {n for n in dir(tristereo.Output) if not n.startswith("_")}
