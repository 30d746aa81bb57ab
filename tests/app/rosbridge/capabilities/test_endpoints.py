"""The lab's `endpoints` op told back (app/rosbridge/capabilities/endpoints.py), as DDS discovery
tells a participant the remote readers and writers: each client with publishers (subscriptions) on a
topic is sent the other clients' subscriptions (publishers) there, with their client's name, when it
tells its own and whenever the others' change, a client that leaves included."""

from tests.app.rosbridge.clients import connect, op, parts, run, sent, until

QOS = {"reliability": "BEST_EFFORT", "durability": "VOLATILE", "deadline": 0}


def told(session, kind: str) -> list[list[dict]]:
    """The entity lists of `kind` the client was sent, in order."""
    return [m["entities"] for m in sent(session, "endpoints") if m["kind"] == kind and m["name"] == "/chatter"]


def test_each_client_is_told_the_others_endpoints_of_the_paired_kind_as_they_change():
    async def check() -> None:
        lab = parts()
        talker, listener, bystander = await connect(lab), await connect(lab), await connect(lab)
        await op(talker, op="node", name="/talker")
        await op(listener, op="node", name="/listener")
        publisher = {"node": "/talker", "qos": QOS}
        assert await op(talker, op="endpoints", kind="publisher", name="/chatter", entities=[publisher]) == []
        subscription = {"node": "/listener", "qos": {}}
        answer = await op(listener, op="endpoints", kind="subscription", name="chatter", entities=[subscription])
        assert answer == [{"op": "endpoints", "kind": "publisher", "name": "/chatter",
                           "entities": [{**publisher, "client": "/talker"}]}]  # fmt: skip
        await until(lambda: told(talker, "subscription"), "the talker told of the listener")
        assert told(talker, "subscription") == [[{**subscription, "client": "/listener"}]]
        # a client with entities of the same kind only, or with none there, is told nothing
        await op(bystander, op="endpoints", kind="publisher", name="/chatter", entities=[{"node": "/b", "qos": {}}])
        await until(lambda: len(told(listener, "publisher")) == 2, "the listener told of the second publisher")
        assert told(listener, "publisher")[-1] == [
            {**publisher, "client": "/talker"},
            {"node": "/b", "qos": {}, "client": "/rosbridge_client_3"},
        ]
        assert sent(bystander, "endpoints") == [  # its answer: the listener's subscription
            {"op": "endpoints", "kind": "subscription", "name": "/chatter",
             "entities": [{**subscription, "client": "/listener"}]}]  # fmt: skip
        # the talker's publisher destroyed, then the bystander gone: the listener told each time
        await op(talker, op="endpoints", kind="publisher", name="/chatter", entities=[])
        await until(lambda: len(told(listener, "publisher")) == 3, "the listener told the talker's is gone")
        assert told(listener, "publisher")[-1] == [{"node": "/b", "qos": {}, "client": "/rosbridge_client_3"}]
        await bystander.close()
        await until(lambda: len(told(listener, "publisher")) == 4, "the listener told the bystander left")
        assert told(listener, "publisher")[-1] == []
        assert len(told(talker, "subscription")) == 1  # the talker, with no publisher left, was told no more
        # service clients are listed, never paired
        assert await op(listener, op="endpoints", kind="client", name="/add", entities=[subscription]) == []

    run(check())


def test_a_bad_endpoints_frame_is_refused_by_name_and_changes_nothing():
    async def check() -> None:
        lab = parts()
        talker, listener = await connect(lab), await connect(lab)
        await op(listener, op="endpoints", kind="subscription", name="/chatter", entities=[{"node": "/l", "qos": {}}])
        refusals = {
            'endpoints: field \'entities\' must be an array, got {"node": "/t"}': {"entities": {"node": "/t"}},
            "endpoints: each entity must be an object with 'node' and 'qos'": {"entities": ["/t"]},
            "endpoints: an entity's 'node' must be a node's full name, e.g. /talker": {"entities": [{"qos": {}}]},
            "endpoints: qos field 'reliability' must be a name or a finite number": {
                "entities": [{"node": "/t", "qos": {"reliability": None}}]
            },
        }
        for reason, fields in refusals.items():
            frame = {"op": "endpoints", "kind": "publisher", "name": "/chatter", **fields}
            answer = await op(talker, **frame)
            assert [m["msg"] for m in answer if m["op"] == "status"] == [reason], answer
        assert sent(listener, "endpoints") == []
        assert talker.endpoints("publisher", "/chatter") == []

    run(check())
