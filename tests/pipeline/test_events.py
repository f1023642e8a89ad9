"""Events of the generation engine: the model's text is passed on in batches."""

from __future__ import annotations

from skillwright.pipeline.events import ChunkBatcher, Notice, TokenChunk


class _Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_chunks_within_the_interval_are_joined_and_other_events_keep_their_order() -> None:
    sent: list[object] = []
    clock = _Clock()
    batcher = ChunkBatcher(sent.append, interval=0.05, clock=clock)
    batcher(TokenChunk("a"))  # the first goes at once, so a UI shows the model has started
    for text in "bcd":
        clock.now += 0.01
        batcher(TokenChunk(text))
    notice = Notice("info", "repairing")
    batcher(notice)
    clock.now += 0.1
    batcher(TokenChunk("e"))
    batcher(TokenChunk("f"))
    batcher.flush()
    assert sent == [TokenChunk("a"), TokenChunk("bcd", 3), notice, TokenChunk("e"), TokenChunk("f")]
    # Each joined event says how many of the stream's chunks (tokens) it holds.
    assert [e.pieces for e in sent if isinstance(e, TokenChunk)] == [1, 3, 1, 1]


def test_flush_without_pending_text_sends_nothing() -> None:
    sent: list[object] = []
    ChunkBatcher(sent.append).flush()
    assert sent == []
