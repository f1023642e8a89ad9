"""Reading a capability model into a :class:`~skillwright.capability.model.Capability`.

The reader follows the ontology design patterns of the CaSk family as the models use
them, in each generation's namespaces (:mod:`skillwright.capability.terms`); where a
model leaves something out it records a warning rather than failing, so later stages can
still work with what is there.
"""

from __future__ import annotations

import re
import threading
from collections.abc import Iterable, Sequence
from decimal import Decimal
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from skillwright.cancel import raise_if_cancelled
from skillwright.capability.model import (
    Capability,
    CapabilityChoice,
    CapabilityLoad,
    Constraint,
    DataElement,
    Expression,
    Parameter,
    Resource,
    ResourceProperty,
    Scalar,
)
from skillwright.capability.rdf import parse_graph
from skillwright.capability.terms import (
    CAPABILITY_CLASSES,
    CSS,
    DIN_NAMESPACES,
    INPUT_PROPERTIES,
    OM,
    OUTPUT_PROPERTIES,
    STATE_CLASSES,
    VDI3682_NAMESPACES,
    closure,
    short,
)
from skillwright.errors import CapabilityError, CapabilitySelectionError

if TYPE_CHECKING:
    from rdflib import Graph
    from rdflib.term import Node

__all__ = ["load_capability", "local_name", "readable_label"]

_DIN_STRUCTURE = {"Instance_Description", "Type_Description", "Data_Element"}

# OpenMath symbols (content dictionary#name) -> (written form, infix?)
OPERATORS: dict[str, tuple[str, bool]] = {
    "relation1#eq": ("=", True),
    "relation1#neq": ("!=", True),
    "relation1#lt": ("<", True),
    "relation1#gt": (">", True),
    "relation1#leq": ("<=", True),
    "relation1#geq": (">=", True),
    "relation1#approx": ("~", True),
    "arith1#plus": ("+", True),
    "arith1#minus": ("-", True),
    "arith1#times": ("*", True),
    "arith1#divide": ("/", True),
    "arith1#power": ("^", True),
    "arith1#mod": ("mod", True),
    "integer1#remainder": ("mod", True),
    "arith1#abs": ("abs", False),
    "arith1#unary_minus": ("-", False),
    "logic1#and": ("and", True),
    "logic1#or": ("or", True),
    "logic1#not": ("not", False),
}


def local_name(iri: str) -> str:
    """The part of an IRI after its last ``#`` or ``/``."""
    return re.split(r"[#/]", iri.rstrip("/#"))[-1]


def readable_label(name: str) -> str:
    """``getDistanceToNearestObject`` -> ``Get distance to nearest object``."""
    words = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|[_\-]+", " ", name).split()
    if not words:
        return name
    text = " ".join(w if w.isupper() and len(w) > 1 else w.lower() for w in words)
    return text[0].upper() + text[1:]


def _operator(iri: str) -> tuple[str, bool]:
    for key, value in OPERATORS.items():
        if iri.endswith(key):
            return value
    return local_name(iri), False


class _Reader:
    """Walks one graph; holds the namespaces and the warnings collected on the way."""

    def __init__(self, graph: Graph, source: Path, ontology_hint: str) -> None:
        from rdflib import URIRef

        self.graph = graph
        self.source = source
        self.ontology_hint = ontology_hint
        """How the user gives a local ontology, as the messages say it."""
        self.warnings: list[str] = []
        self.uri = URIRef

    # --- small graph helpers -------------------------------------------------
    def objects(self, subject: Node, predicate: str | Iterable[str]) -> list[Node]:
        """The objects of ``predicate`` (or of any of several), sorted, each once."""
        predicates = [predicate] if isinstance(predicate, str) else predicate
        found = {o for p in predicates for o in self.graph.objects(subject, self.uri(p))}
        return sorted(found, key=str)

    def din(self, subject: Node, name: str) -> list[Node]:
        """The objects of the DIN EN 61360 property ``name``, in either namespace."""
        return self.objects(subject, [f"{ns}{name}" for ns in DIN_NAMESPACES])

    def first_din(self, subject: Node, name: str) -> Node | None:
        found = self.din(subject, name)
        return found[0] if found else None

    def text_din(self, subject: Node, name: str) -> str | None:
        node = self.first_din(subject, name)
        return None if node is None else str(node)

    def first(self, subject: Node, predicate: str) -> Node | None:
        found = self.objects(subject, predicate)
        return found[0] if found else None

    def text(self, subject: Node, predicate: str) -> str | None:
        node = self.first(subject, predicate)
        return None if node is None else str(node)

    def types(self, subject: Node) -> set[str]:
        from rdflib import RDF

        return {str(t) for t in self.graph.objects(subject, RDF.type)}

    def described(self, node: Node) -> bool:
        return next(iter(self.graph.predicate_objects(node)), None) is not None

    def scalar(self, node: Node | None) -> Scalar | None:
        from rdflib import Literal

        if node is None:
            return None
        if isinstance(node, Literal):
            if node.ill_typed:  # rdf.parse_graph warned about it; its text is what there is
                return str(node)
            value = node.toPython()
            if isinstance(value, Decimal):
                return float(value)
            if isinstance(value, bool | int | float | str):
                return value
        return str(node)

    # --- data elements -------------------------------------------------------
    def data_type(self, instance: Node | None) -> str | None:
        if instance is None:
            return None
        names = sorted(
            t[len(ns) :]
            for t in self.types(instance)
            for ns in DIN_NAMESPACES
            if t.startswith(ns) and t[len(ns) :] not in _DIN_STRUCTURE
        )
        return names[0] if names else None

    def type_description_of(self, instance: Node) -> Node | None:
        """The type description of the data element(s) an instance description belongs to."""
        from rdflib import URIRef

        elements = {
            e
            for ns in DIN_NAMESPACES
            for e in self.graph.subjects(URIRef(f"{ns}has_Instance_Description"), instance)
        }
        for element in sorted(elements, key=str):
            found = self.first_din(element, "has_Type_Description")
            if found is not None:
                return found
        return None

    def element(
        self, instance: Node | None, type_description: Node | None, fallback_name: str
    ) -> DataElement:
        from rdflib import BNode

        if instance is not None and type_description is None:
            type_description = self.type_description_of(instance)
        unit = definition = None
        if type_description is not None:
            unit = self.text_din(type_description, "Unit_of_Measure")
            definition = self.text_din(type_description, "Definition")
        if instance is None:
            return DataElement(name=fallback_name, unit=unit, definition=definition)
        # A blank node (an instance description written inline) has no IRI to name it by.
        named = not isinstance(instance, BNode)
        return DataElement(
            iri=str(instance) if named else None,
            name=_strip_suffix(local_name(str(instance)), "ID") if named else fallback_name,
            data_type=self.data_type(instance),
            unit=unit,
            definition=definition,
            value=self.scalar(self.first_din(instance, "Value")),
            expression_goal=self.text_din(instance, "Expression_Goal"),
            logic_interpretation=self.text_din(instance, "Logic_Interpretation"),
        )

    # --- inputs and outputs --------------------------------------------------
    def parameter(self, node: Node, direction: Literal["input", "output"]) -> Parameter:
        iri = str(node)
        if not self.described(node):
            self.warnings.append(
                f"{direction} <{iri}> is referenced but not described in {self.source}; "
                "its unit and data type are unknown"
            )
        kinds = sorted({STATE_CLASSES[t] for t in self.types(node) if t in STATE_CLASSES})
        name = local_name(iri)
        data_element = self.first_din(node, "has_Data_Element")
        instances = self.objects(node, [f"{ns}isCharacterizedBy" for ns in VDI3682_NAMESPACES])
        type_description = None
        if data_element is not None:
            instances = instances or self.din(data_element, "has_Instance_Description")
            type_description = self.first_din(data_element, "has_Type_Description")
        components = [self.element(i, type_description, name) for i in instances]
        from rdflib import RDFS

        return Parameter(
            iri=iri,
            name=name,
            direction=direction,
            kind=kinds[0] if kinds else "Information",
            comment=self.text(node, str(RDFS.comment)),
            components=components or [self.element(None, type_description, name)],
        )

    # --- the resource --------------------------------------------------------
    def resource(self, capability: Node, taken: set[str]) -> Resource | None:
        from rdflib import URIRef

        providers = sorted(
            self.graph.subjects(URIRef(f"{CSS}providesCapability"), capability), key=str
        )
        if not providers:
            return None
        if len(providers) > 1:
            self.warnings.append(
                f"several resources provide <{capability}>; using <{providers[0]}>"
            )
        node = providers[0]
        properties: list[ResourceProperty] = []
        covered: set[str] = set(taken)
        for data_element in self.din(node, "has_Data_Element"):
            type_description = self.first_din(data_element, "has_Type_Description")
            instances = [
                i for i in self.din(data_element, "has_Instance_Description") if str(i) not in taken
            ]
            covered.update(str(i) for i in instances)
            name = _strip_suffix(local_name(str(data_element)), "DE")
            properties.append(
                ResourceProperty(
                    iri=str(data_element),
                    name=name,
                    instances=[self.element(i, type_description, name) for i in instances],
                )
            )
        for instance in self.objects(node, [f"{ns}isCharacterizedBy" for ns in VDI3682_NAMESPACES]):
            if str(instance) in covered:
                continue
            name = _strip_suffix(local_name(str(instance)), "ID")
            properties.append(
                ResourceProperty(
                    iri=str(instance), name=name, instances=[self.element(instance, None, name)]
                )
            )
        return Resource(iri=str(node), name=local_name(str(node)), properties=properties)

    # --- constraints ---------------------------------------------------------
    def term(
        self, node: Node, names: dict[str, str], constraint: str, depth: int = 0
    ) -> Expression:
        from rdflib import BNode, Literal
        from rdflib.collection import Collection

        if depth > 32:
            raise CapabilityError(
                f"{self.source}: constraint <{constraint}> nests deeper than 32 levels "
                "(a cyclic openmath:arguments list?)"
            )
        if isinstance(node, Literal):
            return Expression(kind="literal", text=str(self.scalar(node)))
        types = self.types(node)
        if f"{OM}Literal" in types:
            return Expression(kind="literal", text=str(self.scalar(self.first(node, f"{OM}value"))))
        operator = self.first(node, f"{OM}operator")
        if operator is not None or f"{OM}Application" in types:
            arguments_node = self.first(node, f"{OM}arguments")
            arguments = []
            if arguments_node is not None:
                arguments = [
                    self.term(a, names, constraint, depth + 1)
                    for a in Collection(self.graph, arguments_node)
                ]
            symbol, infix = _operator(str(operator)) if operator is not None else ("?", False)
            if infix and len(arguments) >= 2:
                # A relation binds loosest, so its sides need no parentheses; inside
                # arithmetic, nested infix terms keep theirs.
                relation = operator is not None and "relation1#" in str(operator)
                parts = [
                    f"({a.text})" if a.kind == "application" and not relation else a.text
                    for a in arguments
                ]
                text = f" {symbol} ".join(parts)
            else:
                text = f"{symbol}({', '.join(a.text for a in arguments)})"
            return Expression(
                kind="application",
                text=text,
                operator=None if operator is None else str(operator),
                arguments=arguments,
            )
        iri = str(node)
        if isinstance(node, BNode):
            return Expression(kind="variable", text="_")
        if iri in names:
            return Expression(kind="variable", text=names[iri], refers_to=iri)
        if not self.described(node):
            self.warnings.append(
                f"constraint <{constraint}> refers to <{iri}>, "
                f"which {self.source} does not describe"
            )
        return Expression(kind="variable", text=_strip_suffix(local_name(iri), "ID"))

    def constraint(self, node: Node, names: dict[str, str]) -> Constraint:
        iri = str(node)
        expression = self.term(node, names, iri)
        if expression.kind != "application":
            self.warnings.append(f"constraint <{iri}> has no openmath:operator; kept as written")
        operator = expression.operator
        relation = _operator(operator)[0] if operator else "?"
        return Constraint(iri=iri, name=local_name(iri), relation=relation, expression=expression)


def _strip_suffix(name: str, suffix: str) -> str:
    """``inDistance_ID`` -> ``inDistance`` (the name itself when nothing is left)."""
    stripped = re.sub(rf"_?{suffix}$", "", name)
    return stripped or name


def _axioms(
    graphs: Sequence[Graph], kind: Literal["class", "property"]
) -> list[tuple[str, str, str]]:
    """The sub-class (or sub-property) and equivalence axioms between named terms."""
    from rdflib import OWL, RDFS, URIRef

    sub, same = (
        (RDFS.subClassOf, OWL.equivalentClass)
        if kind == "class"
        else (RDFS.subPropertyOf, OWL.equivalentProperty)
    )
    return [
        (str(s), relation, str(o))
        for g in graphs
        for predicate, relation in ((sub, "sub"), (same, "same"))
        for s, o in g.subject_objects(predicate)
        if isinstance(s, URIRef) and isinstance(o, URIRef)
    ]


def _find_capabilities(graph: Graph, classes: set[str]) -> list[tuple[str, list[str]]]:
    from rdflib import RDF, URIRef

    found: dict[str, list[str]] = {}
    for cls in classes:
        for subject in graph.subjects(RDF.type, URIRef(cls)):
            if isinstance(subject, URIRef):
                found.setdefault(str(subject), []).append(short(cls))
    return sorted((iri, sorted(kinds)) for iri, kinds in found.items())


def _named(iri: str) -> str:
    """A term as a message names it: prefixed when it has a usual prefix, else ``<IRI>``."""
    shown = short(iri)
    return f"<{iri}>" if shown == iri else shown


def _nothing_linked(
    reader: _Reader, capability: Node, direction: Literal["input", "output"], looked_for: set[str]
) -> str:
    """The warning for a capability without inputs (or outputs): the properties looked for,
    and the capability's links whose name says input (output) but whose vocabulary is not one
    of those."""
    from rdflib import URIRef

    listed = INPUT_PROPERTIES if direction == "input" else OUTPUT_PROPERTIES
    extra = sorted(looked_for - set(listed))
    names = ", ".join(_named(p) for p in (*listed, *extra))
    message = (
        f"capability <{capability}> has no {direction}s: none is linked by {names} "
        f"(nor by a sub-property or equivalent the file or an ontology declares; give one as "
        f"{reader.ontology_hint})"
    )
    unknown = sorted(
        {
            str(p)
            for p in reader.graph.predicates(capability)
            if isinstance(p, URIRef) and direction in local_name(str(p)).lower()
        }
        - looked_for
    )
    if unknown:
        message += (
            f"; its {', '.join(_named(p) for p in unknown)} links are not {direction}s in "
            "any vocabulary skillwright knows (declare the property a sub-property of "
            f"{_named(listed[0])} to have them read)"
        )
    return message


def _parameters(
    reader: _Reader,
    capability: Node,
    graphs: Sequence[Graph],
    direction: Literal["input", "output"],
) -> list[Parameter]:
    """The capability's inputs (or outputs) by any of the properties that link them; a
    warning names the properties when there are none."""
    listed = INPUT_PROPERTIES if direction == "input" else OUTPUT_PROPERTIES
    properties = closure(listed, _axioms(graphs, "property"))
    found = [reader.parameter(n, direction) for n in reader.objects(capability, properties)]
    if not found:
        reader.warnings.append(_nothing_linked(reader, capability, direction, properties))
    return found


def _select(choices: Sequence[CapabilityChoice], wanted: str | None, source: Path) -> int:
    listing = "\n".join(f"  {choice.iri}" for choice in choices)
    if wanted is None:
        if len(choices) == 1:
            return 0
        raise CapabilitySelectionError(
            f"{source} holds {len(choices)} capabilities; choose one by its IRI (--capability-iri "
            "IRI for generate and retrieve, --capability IRI for capability show):\n" + listing,
            choices,
        )
    matches = [i for i, choice in enumerate(choices) if wanted in (choice.iri, choice.name)]
    if len(matches) == 1:
        return matches[0]
    reason = "matches several" if matches else "is not one of the capabilities"
    raise CapabilitySelectionError(
        f"--capability {wanted} {reason} in {source}:\n{listing}", choices
    )


def load_capability(
    path: str | Path,
    *,
    capability_iri: str | None = None,
    ontologies: Iterable[str | Path] = (),
    cancel: threading.Event | None = None,
    ontology_hint: str = "--ontology FILE",
) -> CapabilityLoad:
    """Reads the capability model at ``path``.

    ``capability_iri`` selects one capability when the file holds several (its full IRI
    or its local name). ``ontologies`` are local copies of imported ontologies; their
    class hierarchy lets domain-specific capability classes be recognised. ``cancel`` is
    looked at before and after each file is parsed (see :mod:`skillwright.cancel`).
    ``ontology_hint`` is how the caller's user gives such a copy, as the messages say it
    (the CLI's ``--ontology FILE``, the TUI's ontologies folder).
    """
    from rdflib import RDFS, URIRef

    from skillwright.capability.vocabulary import load_vocabulary

    what = f"reading {path}"
    raise_if_cancelled(cancel, what)
    source = Path(path)
    parsed = parse_graph(source)
    graph = parsed.graph
    ontology_paths = [Path(p) for p in ontologies]
    vocabulary = load_vocabulary(ontology_paths, cancel=cancel) if ontology_paths else None
    raise_if_cancelled(cancel, what)
    reader = _Reader(graph, source, ontology_hint)
    reader.warnings += parsed.warnings
    if vocabulary is not None:
        reader.warnings += vocabulary.warnings
    graphs = [graph] if vocabulary is None else [graph, vocabulary.graph]

    imports = sorted(
        str(o) for o in graph.objects(None, URIRef("http://www.w3.org/2002/07/owl#imports"))
    )
    provided = vocabulary.ontology_iris if vocabulary else set()
    missing = [i for i in imports if i not in provided]
    if missing:
        reader.warnings.append(
            "owl:imports "
            + ", ".join(f"<{i}>" for i in missing)
            + " not fetched (skillwright works offline); give a local copy as "
            + reader.ontology_hint
        )

    found = _find_capabilities(graph, closure(CAPABILITY_CLASSES, _axioms(graphs, "class")))
    if not found:
        raise CapabilityError(
            f"{source}: no capability found; expected an individual typed "
            + ", ".join(_named(c) for c in CAPABILITY_CLASSES)
            + " (or a subclass declared in the file or in an ontology, given as "
            + f"{reader.ontology_hint})"
        )
    choices = [
        CapabilityChoice(
            iri=iri,
            name=local_name(iri),
            label=reader.text(URIRef(iri), str(RDFS.label)) or readable_label(local_name(iri)),
        )
        for iri, _ in found
    ]
    index = _select(choices, capability_iri, source)
    iri, kinds = found[index]
    node = URIRef(iri)
    label = choices[index].label

    comment = reader.text(node, str(RDFS.comment))
    if not comment:
        reader.warnings.append(
            f"capability <{iri}> has no rdfs:comment; add one sentence saying what it does "
            "(retrieval and generation use it)"
        )
    inputs = _parameters(reader, node, graphs, "input")
    outputs = _parameters(reader, node, graphs, "output")

    names: dict[str, str] = {}
    for parameter in (*inputs, *outputs):
        names[parameter.iri] = parameter.name
        for component in parameter.components:
            if component.iri:
                names[component.iri] = component.name
    resource = reader.resource(node, set(names))
    if resource is not None:
        for prop in resource.properties:
            for instance in prop.instances:
                if instance.iri:
                    names.setdefault(instance.iri, prop.name)
    constraints = [
        reader.constraint(n, names) for n in reader.objects(node, f"{CSS}isRestrictedBy")
    ]
    capability = Capability(
        iri=iri,
        name=local_name(iri),
        label=label,
        kinds=kinds,
        comment=comment,
        inputs=inputs,
        outputs=outputs,
        constraints=constraints,
        resource=resource,
    )
    return CapabilityLoad(
        source=str(source),
        capability=capability,
        others=[other for other, _ in found if other != iri],
        choices=choices,
        warnings=reader.warnings,
    )
