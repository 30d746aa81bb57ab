"""auth, set_level, fragment, png (app/rosbridge/capabilities/connection.py)."""

from tests.app.rosbridge.clients import connect, op, parts, run

TOKEN = "s3cret-0123456789abcdef"


def test_auth_presents_the_token_a_wrong_one_is_refused():
    async def check() -> None:
        session = await connect(parts(token=TOKEN, replay=True))
        assert not session.authorized
        assert (await op(session, op="auth", mac="wrong"))[0]["msg"] == "auth: wrong token"
        assert not session.authorized
        assert await op(session, op="auth", mac=TOKEN) == []
        assert session.authorized
        refused = await op(session, op="auth")
        assert refused[0]["msg"] == "auth: field 'mac' is required"

    run(check())


def test_auth_without_a_token_set_changes_nothing():
    async def check() -> None:
        session = await connect(parts(replay=True))
        assert session.authorized
        assert await op(session, op="auth", mac="anything") == []
        assert session.authorized

    run(check())


def test_set_level_shows_that_level_and_the_ones_after_it_a_bad_level_is_dropped():
    async def check() -> None:
        session = await connect(parts(replay=True))
        assert await op(session, op="unsubscribe", topic="/never") == []  # a warning: hidden at "error"
        await op(session, op="set_level", level="warning")
        assert session.level == "warning"
        shown = await op(session, op="unsubscribe", topic="/never")
        assert shown[0]["level"] == "warning"
        assert "not subscribed to /never" in shown[0]["msg"]
        await op(session, op="set_level", level="loud")
        assert session.level == "warning"
        await op(session, op="set_level", level="none")
        assert await op(session, op="teleport") == []

    run(check())


def test_fragment_and_png_are_refused_with_the_reason():
    async def check() -> None:
        session = await connect(parts(replay=True))
        assert "fragmented messages are not supported" in (await op(session, op="fragment", id="f"))[0]["msg"]
        assert "PNG-compressed messages are not supported" in (await op(session, op="png"))[0]["msg"]

    run(check())
