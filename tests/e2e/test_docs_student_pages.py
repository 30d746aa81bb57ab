"""The students' pages run as written (tests/e2e/docs_commands.py): docs/students.md and
docs/ros-programs-client.md, every command in order against a real lab."""

from tests.e2e.docs_commands import DOCS, page_commands, run_page, split_comment


def test_the_convention_is_read_as_the_pages_state_it():
    assert split_comment(".venv/bin/hri-lab service call /echo '{in: \"a # b\"}'   # one # comment") == (
        ".venv/bin/hri-lab service call /echo '{in: \"a # b\"}'",
        "one # comment",
    )
    commands = page_commands("students.md")
    assert [c.command for c in commands if c.background] == [
        ".venv/bin/hri-lab serve --controller cooperative_lifting.py",
        ".venv/bin/hri-lab serve --exercises",
        ".venv/bin/hri-lab run services_node.py",
        ".venv/bin/hri-lab serve",
        ".venv/bin/hri-lab run lifting_node.py",
    ]
    assert {c.exit_status for c in commands} == {0, 1}
    for page in ("students.md", "ros-programs-client.md", "mobile-lab.md"):  # one lab per port, said where labs start
        assert "(getting-started.md#one-lab-per-port)" in (DOCS / page).read_text(), page
    for page in ("students.md", "ros-programs-client.md", "instructors.md", "course-scale.md"):
        for command in page_commands(page):
            assert command.run or command.comment.split("(not run by the docs test:")[1].strip(" )"), command.line


def test_the_students_page(tmp_path):
    run = run_page("students.md", tmp_path / "students")
    said = "\n".join(run.transcript)
    assert said.count("# beside the running lab") == 2  # each lab after the first, started beside the one before
    assert "score: 15/130" in said  # the unfilled controller template, as the page states
    assert "seed 0, the public default" in said
    assert "score: 1/15" in said  # the unfilled services node: the done example only
    assert "Cooperative lifting starts with 10 N" in said  # the lifting node's start answered the call
    lifting_node = next(b for b in run.background if "lifting_node.py" in b.command.command)
    assert "/start_cooperative_lifting is one of the lab's own services" in lifting_node.output()  # the warning


def test_the_handout_programs_page(tmp_path):
    run = run_page("ros-programs-client.md", tmp_path / "programs")
    said = "\n".join(run.transcript)
    assert "20 + 22 = 42" in said
    assert "score: 1/15" in said
