"""Printer validation, part 3: the C side — the printed glue and its header
parsed with pycparser, types recovered from the declarations, normalised
like the dump (:mod:`printer_types`).
"""

from __future__ import annotations

import re
from pyrosgen.verify.printer_types import (
    C_BINOPS,
    C_UNOPS,
    F32_HELPER,
    F64,
    F64_HELPER,
    INT,
    LLONG,
    VOID,
    ValidationReport,
    _C_INT_TYPES,
    _Diff,
    _HELPER_TEXT,
    _HELPER_TYPE,
    _binop_type,
    _unop_type,
    _float_literal,
    _int_literal,
    _is_arith,
    _is_int,
    _is_scalar,
    _wrap,
    show_type,
    typeof,
)

# ---------------------------------------------------------------------------
# The C side

def _strip_comments(text: str) -> str:
    """Comments replaced by spaces (newlines kept, so lines keep their
    numbers)."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            if j < 0:
                raise _Diff("unterminated comment")
            out.append("".join(c if c == "\n" else " " for c in text[i:j + 2]))
            i = j + 2
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text[i] in "\"'":
            q, j = text[i], i + 1
            while j < n and text[j] != q:
                if text[j] == "\n":
                    raise _Diff("unterminated literal")
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


def _directives(text: str) -> list[tuple[int, str]]:
    return [(k, line.strip()) for k, line in enumerate(text.split("\n"), 1) if line.lstrip().startswith("#")]


def _header_body(header_text: str, header_name: str) -> tuple[str, int]:
    """The text inside the include guard of the types header (directives
    blanked), and the line where it starts."""
    text = _strip_comments(header_text)
    dirs = _directives(text)
    if len(dirs) != 3:
        raise _Diff(f"{header_name}: expected exactly #ifndef/#define/#endif, found {len(dirs)} directives")
    (l1, d1), (l2, d2), (l3, d3) = dirs
    m1 = re.fullmatch(r"#\s*ifndef\s+([A-Za-z_]\w*)", d1)
    m2 = re.fullmatch(r"#\s*define\s+([A-Za-z_]\w*)", d2)
    if not (m1 and m2 and m1.group(1) == m2.group(1) and l2 == l1 + 1 and re.fullmatch(r"#\s*endif", d3)):
        raise _Diff(f"{header_name}: not an include-guarded header (#ifndef G / #define G ... #endif)",
                    detail=(d1, d2, d3))
    lines = text.split("\n")
    if any(line.strip() for line in lines[: l1 - 1] + lines[l3:]):
        raise _Diff(f"{header_name}: text outside the include guard")
    body = "\n".join(lines[l2:l3 - 1])
    return body, l2 + 1


def _translation_unit(glue_text: str, glue_name: str, header_text: str | None,
                      header_name: str | None) -> str:
    """The glue with the types header inlined, with line markers so that
    pycparser reports the original files and lines."""
    text = _strip_comments(glue_text)
    dirs = _directives(text)
    if header_name is None:
        if dirs:
            raise _Diff(f"{glue_name}:{dirs[0][0]}: unexpected directive {dirs[0][1]}")
        return f'# 1 "{glue_name}"\n' + text
    if len(dirs) != 1:
        raise _Diff(f"{glue_name}: expected exactly one directive (#include \"{header_name}\"), "
                    f"found {len(dirs)}")
    line, d = dirs[0]
    m = re.fullmatch(r'#\s*include\s+"([^"]+)"', d)
    if not m or m.group(1) != header_name:
        raise _Diff(f"{glue_name}:{line}: expected #include \"{header_name}\", found {d}")
    body, start = _header_body(header_text, header_name)
    lines = text.split("\n")
    return "\n".join([f'# 1 "{glue_name}"', *lines[: line - 1],
                      f'# {start} "{header_name}"', body,
                      f'# {line + 1} "{glue_name}"', *lines[line:]])


def _parse_error() -> type:
    """pycparser's ParseError (its module moved in pycparser 3)."""
    try:
        from pycparser.c_parser import ParseError
    except ImportError:  # pycparser 2.x
        from pycparser.plyparser import ParseError
    return ParseError


class _CProgram:
    """Normalises a translation unit parsed by pycparser."""

    def __init__(self, ast, report: ValidationReport):
        from pycparser import c_ast

        self.c_ast = c_ast
        self.report = report
        self.structs: dict[str, list] = {}
        self.struct_order: list[str] = []
        self.struct_coord: dict[str, object] = {}
        self.gvars: list[tuple[str, tuple, bool, object]] = []   # name, type, extern, node
        self.protos: list[tuple[str, tuple, list, object]] = []  # name, type, param names, node
        self.defs: list[tuple] = []   # name, type, param names, locals, body(), node
        self.scope: dict[str, tuple[str, tuple]] = {}            # file scope: name -> (kind, type)
        self.helpers_defined: dict[str, object] = {}
        self.helpers_used: set[str] = set()
        for ext in ast.ext:
            self._external(ext)

    # -- types ---------------------------------------------------------------

    def ctype(self, node, *, param: bool = False) -> tuple:
        a = self.c_ast
        if isinstance(node, a.TypeDecl):
            if node.quals:
                raise _Diff(f"qualifier {' '.join(node.quals)} is not in the printed subset", node.coord)
            inner = node.type
            if isinstance(inner, a.IdentifierType):
                key = tuple(sorted(inner.names))
                t = _C_INT_TYPES.get(key)
                if t is None:
                    raise _Diff(f"type {' '.join(inner.names)} is not in the printed subset", node.coord)
                return t
            if isinstance(inner, a.Struct):
                if inner.decls is not None:
                    raise _Diff(f"struct {inner.name} defined inside a declaration", node.coord)
                if inner.name not in self.structs:
                    raise _Diff(f"struct {inner.name} used before its definition", node.coord)
                return ("struct", inner.name)
            raise _Diff(f"type {type(inner).__name__} is not in the printed subset", node.coord)
        if isinstance(node, a.PtrDecl):
            if node.quals:
                raise _Diff("qualified pointer is not in the printed subset", node.coord)
            t = ("ptr", self.ctype(node.type))
        elif isinstance(node, a.ArrayDecl):
            if node.dim_quals or not isinstance(node.dim, a.Constant):
                raise _Diff("array without a constant size", node.coord)
            n, _ = _int_literal(node.dim.value)
            t = ("array", self.ctype(node.type), n)
        elif isinstance(node, a.FuncDecl):
            t = ("fun", tuple(p for _, p in self.params(node)), self.ctype(node.type))
        else:
            raise _Diff(f"declarator {type(node).__name__} is not in the printed subset", node.coord)
        if param and t[0] == "array":       # C11 6.7.6.3p7-8: parameter adjustment
            t = ("ptr", t[1])
        elif param and t[0] == "fun":
            t = ("ptr", t)
        return t

    def params(self, fdecl) -> list[tuple[str | None, tuple]]:
        a = self.c_ast
        if fdecl.args is None:
            raise _Diff("function declarator without a prototype", fdecl.coord)
        ps = fdecl.args.params
        if (len(ps) == 1 and isinstance(ps[0], a.Typename) and isinstance(ps[0].type, a.TypeDecl)
                and isinstance(ps[0].type.type, a.IdentifierType) and ps[0].type.type.names == ["void"]
                and not ps[0].quals):
            return []
        out = []
        for p in ps:
            if isinstance(p, a.EllipsisParam):
                raise _Diff("variadic function", p.coord)
            if isinstance(p, a.Decl):
                if p.storage or p.init is not None or p.funcspec or p.quals:
                    raise _Diff(f"parameter {p.name} with a storage class, qualifier or initialiser", p.coord)
                out.append((p.name, self.ctype(p.type, param=True)))
            elif isinstance(p, a.Typename):
                if p.quals:
                    raise _Diff("qualified parameter", p.coord)
                out.append((None, self.ctype(p.type, param=True)))
            else:
                raise _Diff(f"parameter {type(p).__name__}", p.coord)
        return out

    # -- file scope ------------------------------------------------------------

    def _declare(self, name: str, kind: str, t: tuple, node) -> None:
        if name in self.scope:
            old_kind, old_t = self.scope[name]
            # a function definition after its prototype is the one allowed redeclaration
            if not (kind == "function" and old_kind == "function" and old_t == t):
                raise _Diff(f"{name} declared twice", node.coord)
        self.scope[name] = (kind, t)

    def _external(self, ext) -> None:
        a = self.c_ast
        if isinstance(ext, a.Decl) and isinstance(ext.type, a.Struct):
            st = ext.type
            if ext.name is not None or ext.storage or ext.quals or st.decls is None or st.name is None:
                raise _Diff("a declaration other than a struct definition", ext.coord)
            if st.name in self.structs:
                raise _Diff(f"struct {st.name} defined twice", ext.coord)
            members = []
            for d in st.decls:
                if not isinstance(d, a.Decl) or d.bitsize is not None or d.init is not None or d.quals:
                    raise _Diff(f"member of struct {st.name} not in the printed subset", d.coord)
                t = self.ctype(d.type)
                if t[0] in ("fun", "void"):
                    raise _Diff(f"member {d.name} of struct {st.name} has type {show_type(t)}", d.coord)
                members.append((d.name, t))
            self.structs[st.name] = members
            self.struct_order.append(st.name)
            self.struct_coord[st.name] = ext.coord
            self.report.structs += 1
            return
        if isinstance(ext, a.Decl) and isinstance(ext.type, a.FuncDecl):
            if ext.storage or ext.funcspec or ext.quals or ext.init is not None:
                raise _Diff(f"prototype of {ext.name} with a storage class or specifier", ext.coord)
            ps = self.params(ext.type)
            t = ("fun", tuple(p for _, p in ps), self.ctype(ext.type.type))
            self._declare(ext.name, "function", t, ext)
            self.protos.append((ext.name, t, [n for n, _ in ps], ext))
            return
        if isinstance(ext, a.Decl):
            if ext.storage not in ([], ["extern"]) or ext.funcspec or ext.quals:
                raise _Diff(f"global {ext.name} with storage class {' '.join(ext.storage)}", ext.coord)
            if ext.init is not None:
                raise _Diff(f"global {ext.name} has an initialiser", ext.coord)
            t = self.ctype(ext.type)
            if t[0] == "void":
                raise _Diff(f"global {ext.name} of type void", ext.coord)
            self._declare(ext.name, "global", t, ext)
            self.gvars.append((ext.name, t, ext.storage == ["extern"], ext))
            return
        if isinstance(ext, a.FuncDef):
            self._function(ext)
            return
        raise _Diff(f"{type(ext).__name__} at file scope is not in the printed subset", ext.coord)

    def _function(self, fd) -> None:
        a = self.c_ast
        decl = fd.decl
        name = decl.name
        if fd.param_decls:
            raise _Diff(f"K&R definition of {name}", fd.coord)
        if name in _HELPER_TEXT:
            self._helper(fd)
            return
        if decl.storage or decl.funcspec or decl.quals:
            raise _Diff(f"function {name} with a storage class or specifier", fd.coord)
        ps = self.params(decl.type)
        if any(n is None for n, _ in ps):
            raise _Diff(f"function {name} has an unnamed parameter", fd.coord)
        t = ("fun", tuple(p for _, p in ps), self.ctype(decl.type.type))
        self._declare(name, "function", t, fd)
        items = fd.body.block_items or []
        local_types: dict[str, tuple] = {}
        for n, pt in ps:
            if n in local_types:
                raise _Diff(f"parameter {n} of {name} declared twice", fd.coord)
            local_types[n] = pt
        locals_: list[tuple[str, tuple]] = []
        k = 0
        while k < len(items) and isinstance(items[k], a.Decl):
            d = items[k]
            if d.storage or d.init is not None or d.funcspec or d.quals or isinstance(d.type, a.FuncDecl):
                raise _Diff(f"local {d.name} of {name} not in the printed subset", d.coord)
            lt = self.ctype(d.type)
            if d.name in local_types:
                raise _Diff(f"local {d.name} of {name} declared twice", d.coord)
            local_types[d.name] = lt
            locals_.append((d.name, lt))
            k += 1
        # the body is normalised when it is compared (after the declarations),
        # with the file-scope names declared before the definition
        fn = _CFunction(self, name, t, local_types, frozenset(self.scope))
        stmts = items[k:]

        def body() -> tuple[tuple, dict]:
            coords: dict[tuple, object] = {}
            try:
                return fn.stmts(stmts, (), coords), coords
            except _Diff as d:
                raise _Diff(f"function {name}: {d.message}", d.coord, d.detail) from None

        self.defs.append((name, t, [n for n, _ in ps], locals_, body, fd))
        self.report.functions += 1

    def _helper(self, fd) -> None:
        from pycparser import c_generator, c_parser

        name = fd.decl.name
        expected = c_parser.CParser().parse(_HELPER_TEXT[name]).ext[0]
        gen = c_generator.CGenerator()
        if gen.visit(fd) != gen.visit(expected):
            raise _Diff(f"helper {name} is not the documented definition", fd.coord,
                        detail=("C:  " + " ".join(gen.visit(fd).split()),
                                "doc: " + " ".join(gen.visit(expected).split())))
        if name in self.scope:
            raise _Diff(f"{name} declared twice", fd.coord)
        order = list(_HELPER_TEXT)
        later = [h for h in self.helpers_defined if order.index(h) > order.index(name)]
        if later:
            raise _Diff(f"helper {name} defined after {later[0]} (the printer's order: "
                        f"{', '.join(order)})", fd.coord)
        self.scope[name] = ("helper", _HELPER_TYPE[name])
        self.helpers_defined[name] = fd


class _CFunction:
    """Normalises the body of one C function."""

    def __init__(self, prog: _CProgram, name: str, ftype: tuple, local_types: dict,
                 visible: frozenset):
        self.prog = prog
        self.visible = visible
        self.a = prog.c_ast
        self.name = name
        self.ret = ftype[2]
        self.locals = local_types

    # -- expressions -------------------------------------------------------------

    def const(self, node) -> tuple | None:
        """The value of a constant expression of the printed subset, or
        None if [node] is not one."""
        a = self.a
        if isinstance(node, a.Constant):
            self.prog.report.constants += 1
            if node.type in ("float", "double", "long double"):
                b, t = _float_literal(node.value)
                return ("constf", b, t)
            if "char" in node.type or "string" in node.type:
                raise _Diff(f"constant {node.value} is not in the printed subset", node.coord)
            v, t = _int_literal(node.value)
            return ("const", v, t)
        if isinstance(node, a.UnaryOp) and node.op == "-" and isinstance(node.expr, a.Constant):
            # a sign before a literal: the printer's negative constants
            # ([-5], [-5LL], [-0x1p+0]); [-5U] is an operation
            c = self.const(node.expr)
            if c[0] == "constf":
                return ("constf", c[1] ^ (1 << (63 if c[2] == F64 else 31)), c[2])
            if c[2] in (INT, LLONG):
                return ("const", -c[1], c[2])     # the literal is at most the maximum
            return None
        if isinstance(node, a.BinaryOp) and node.op == "-":
            # [(-2147483647 - 1)] and [(-9223372036854775807LL - 1)]: the minimum values
            if isinstance(node.left, a.UnaryOp) and isinstance(node.right, a.Constant):
                l, r = self.const(node.left), self.const(node.right)
                if l is not None and r == ("const", 1, INT):
                    for t, bits in ((INT, 32), (LLONG, 64)):
                        if l == ("const", -(1 << (bits - 1)) + 1, t):
                            return ("const", -(1 << (bits - 1)), t)
            return None
        return None

    def expr(self, node) -> tuple:
        a = self.a
        self.prog.report.expressions += 1
        c = self.const(node)
        if c is not None:
            return c
        if isinstance(node, a.ID):
            x = node.name
            if x in self.locals:
                return ("ref", "local", x, self.locals[x])
            if x in self.visible:
                kind, t = self.prog.scope[x]
                if kind == "helper":
                    raise _Diff(f"{x} used other than called", node.coord)
                return ("ref", kind, x, t)
            raise _Diff(f"{x} is not declared", node.coord)
        if isinstance(node, a.UnaryOp) and node.op == "*":
            e = self.expr(node.expr)
            if typeof(e)[0] != "ptr":
                raise _Diff(f"dereference of a {show_type(typeof(e))}", node.coord)
            return ("deref", e, typeof(e)[1])
        if isinstance(node, a.UnaryOp) and node.op == "&":
            e = self.expr(node.expr)
            if e[0] not in ("ref", "deref", "field", "index") or (e[0] == "ref" and e[1] not in ("local", "global", "function")):
                raise _Diff("address of a non-lvalue", node.coord)
            return ("addrof", e, ("ptr", typeof(e)))
        if isinstance(node, a.StructRef):
            e = self.expr(node.name)
            if node.type == "->":
                if typeof(e)[0] != "ptr":
                    raise _Diff(f"-> applied to a {show_type(typeof(e))}", node.coord)
                e = ("deref", e, typeof(e)[1])
            t = typeof(e)
            if t[0] != "struct":
                raise _Diff(f"field {node.field.name} of a {show_type(t)}", node.coord)
            members = dict(self.prog.structs[t[1]])
            f = node.field.name
            if f not in members:
                raise _Diff(f"struct {t[1]} has no member {f}", node.coord)
            return ("field", e, f, members[f])
        if isinstance(node, a.ArrayRef):
            e, i = self.expr(node.name), self.expr(node.subscript)
            if typeof(e)[0] != "array" or not _is_int(typeof(i)):
                raise _Diff("subscript other than of an array by an integer", node.coord)
            return ("index", e, i, typeof(e)[1])
        if isinstance(node, a.Cast):
            if node.to_type.quals:
                raise _Diff("qualified cast", node.coord)
            e = self.expr(node.expr)
            return ("cast", e, self.prog.ctype(node.to_type.type))
        if isinstance(node, a.FuncCall) and isinstance(node.name, a.ID) and node.name.name in _HELPER_TEXT:
            h = node.name.name
            if h not in self.visible:
                raise _Diff(f"{h} used before its definition", node.coord)
            args = node.args.exprs if node.args is not None else []
            _, (want,), res = _HELPER_TYPE[h]
            if h in (F64_HELPER, F32_HELPER):
                arg = self.const(args[0]) if len(args) == 1 else None
                if arg is None or arg[0] != "const" or arg[2] != want:
                    raise _Diff(f"{h} applied to something else than one {show_type(want)} constant", node.coord)
                self.prog.helpers_used.add(h)
                return ("constf", arg[1], res)
            # rosgen_fabs / rosgen_fabsf: [Oabsfloat] on a double / a float
            if len(args) != 1:
                raise _Diff(f"{h} applied to {len(args)} arguments", node.coord)
            arg = self.expr(args[0])
            if typeof(arg) != want:
                raise _Diff(f"{h} applied to a {show_type(typeof(arg))} (implicit conversion "
                            f"to {show_type(want)})", node.coord)
            self.prog.helpers_used.add(h)
            return ("unop", "absfloat", arg, res)
        if isinstance(node, a.UnaryOp) and node.op in C_UNOPS:
            op = C_UNOPS[node.op]
            e = self.expr(node.expr)
            try:
                return ("unop", op, e, _unop_type(op, typeof(e)))
            except _Diff as d:
                raise _Diff(d.message, node.coord) from None
        if isinstance(node, a.BinaryOp) and node.op in C_BINOPS:
            op = C_BINOPS[node.op]
            e1, e2 = self.expr(node.left), self.expr(node.right)
            try:
                return ("binop", op, e1, e2, _binop_type(op, typeof(e1), typeof(e2)))
            except _Diff as d:
                raise _Diff(d.message, node.coord) from None
        raise _Diff(f"expression {type(node).__name__}"
                    f"{' ' + node.op if hasattr(node, 'op') else ''} is not in the printed subset", node.coord)

    def converted(self, e: tuple, target: tuple, node, what: str, *, assignment: bool) -> None:
        """Check the implicit conversion of [e] to [target] that C performs
        in an assignment (or argument passing, or return)."""
        t = typeof(e)
        if t == target:
            return
        if e[0] == "const" and t == INT and target[0] == "int" and _wrap(target, e[1]) == e[1]:
            return  # an 8/16-bit constant, printed as an int literal of the same value
        if not assignment and _is_arith(t) and _is_arith(target):
            return  # arguments: converted as by a cast, as eval_exprlist does
        raise _Diff(f"{what}: implicit conversion from {show_type(t)} to {show_type(target)}", node.coord)

    # -- statements ----------------------------------------------------------------

    def block(self, node, path, coords) -> tuple:
        a = self.a
        if node is None:
            return ()
        if isinstance(node, a.Compound):
            return self.stmts(node.block_items or [], path, coords)
        return self.stmts([node], path, coords)

    def stmts(self, items, path: tuple, coords: dict) -> tuple:
        a = self.a
        out: list = []
        for node in items:
            if isinstance(node, a.Compound):
                for s in self.block(node, path + (len(out),), {}):
                    coords[path + (len(out),)] = node.coord
                    out.append(s)
                continue
            if isinstance(node, a.EmptyStatement):
                continue
            here = path + (len(out),)
            coords[here] = node.coord
            self.prog.report.statements += 1
            out.append(self.stmt(node, here, coords))
        return tuple(out)

    def stmt(self, node, path, coords) -> tuple:
        a = self.a
        if isinstance(node, a.Assignment):
            if node.op != "=":
                raise _Diff(f"compound assignment {node.op}", node.coord)
            lhs = self.expr(node.lvalue)
            if lhs[0] not in ("ref", "deref", "field", "index") or (lhs[0] == "ref" and lhs[1] not in ("local", "global")):
                raise _Diff("assignment to a non-lvalue", node.coord)
            if typeof(lhs)[0] in ("array", "fun", "void"):
                raise _Diff(f"assignment of a {show_type(typeof(lhs))}", node.coord)
            if isinstance(node.rvalue, a.FuncCall) and not (
                    isinstance(node.rvalue.name, a.ID) and node.rvalue.name.name in _HELPER_TEXT):
                if lhs[0] != "ref" or lhs[1] != "local":
                    raise _Diff("a call result stored elsewhere than in a local", node.coord)
                f, args = self.call(node.rvalue)
                self.converted(("call-result", typeof(f)[2]), typeof(lhs), node, "call result", assignment=True)
                return ("call", lhs, f, args)
            rhs = self.expr(node.rvalue)
            self.converted(rhs, typeof(lhs), node, "assignment", assignment=True)
            return ("assign", lhs, rhs)
        if isinstance(node, a.FuncCall):
            f, args = self.call(node)
            return ("call", None, f, args)
        if isinstance(node, a.If):
            c = self.expr(node.cond)
            if not _is_scalar(typeof(c)):
                raise _Diff(f"condition of type {show_type(typeof(c))}", node.coord)
            return ("if", c, self.block(node.iftrue, path + ("then",), coords),
                    self.block(node.iffalse, path + ("else",), coords))
        if isinstance(node, a.For):
            if node.init is not None or node.cond is not None or node.next is not None:
                raise _Diff("for loop other than for (;;)", node.coord)
            return ("loop", self.block(node.stmt, path + ("body",), coords))
        if isinstance(node, a.While):
            c = self.expr(node.cond)
            if not _is_scalar(typeof(c)):
                raise _Diff(f"condition of type {show_type(typeof(c))}", node.coord)
            body = self.block(node.stmt, path + ("body",), coords)
            # while (c) s  =  for (;;) { if (c) { } else { break; } s }
            shifted = {k[:len(path) + 1] + (k[len(path) + 1] + 1,) + k[len(path) + 2:]: v
                       for k, v in coords.items() if k[:len(path) + 1] == path + ("body",) and len(k) > len(path) + 1}
            for k in [k for k in coords if k[:len(path) + 1] == path + ("body",) and len(k) > len(path) + 1]:
                del coords[k]
            coords.update(shifted)
            coords[path + ("body", 0)] = node.coord
            return ("loop", (("if", c, (), (("break",),)),) + body)
        if isinstance(node, a.Break):
            return ("break",)
        if isinstance(node, a.Return):
            if node.expr is None:
                if self.ret != VOID:
                    raise _Diff("return without a value in a non-void function", node.coord)
                return ("return", None)
            e = self.expr(node.expr)
            if self.ret == VOID:
                raise _Diff("return with a value in a void function", node.coord)
            self.converted(e, self.ret, node, "return", assignment=False)
            return ("return", e)
        raise _Diff(f"statement {type(node).__name__} is not in the printed subset", node.coord)

    def call(self, node) -> tuple[tuple, tuple]:
        f = self.expr(node.name)
        ft = typeof(f)
        if ft[0] != "fun":
            raise _Diff(f"call of a {show_type(ft)}", node.coord)
        args = tuple(self.expr(x) for x in (node.args.exprs if node.args is not None else []))
        if len(args) != len(ft[1]):
            raise _Diff(f"call with {len(args)} arguments of a function of {len(ft[1])} parameters", node.coord)
        for k, (arg, pt) in enumerate(zip(args, ft[1])):
            if typeof(arg) != pt and not (_is_arith(typeof(arg)) and _is_arith(pt)):
                raise _Diff(f"argument {k + 1}: implicit conversion from {show_type(typeof(arg))} "
                            f"to {show_type(pt)}", node.coord)
        return f, args
