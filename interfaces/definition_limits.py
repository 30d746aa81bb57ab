"""The caps on a ROS interface definition's text (.msg, .srv, .action) wherever one is read: in a
program and in the lab (interfaces/parser.py), and in a bag's carried definitions
(app/recording/bags.py). A definition beyond one is refused naming the cap, before anything is built
from it (a model, a default message, a type store's classes)."""

MAX_DEFINITION_CHARS = 65_536  # characters of one definition's text (a file, or a type a client carries)
MAX_FIXED_ARRAY = 65_536  # items of a fixed-size array (T[N]); a bound (T[<=N], string<=N) has at most 9 digits
MAX_DEFAULT_VALUES = 65_536  # values a message's default holds, nested messages' and fixed arrays' items counted
# fields of a definition's types, each type counted once (a service's models at the cap: ~2 MiB, 0.09 s of CPU)
MAX_DEFINITION_FIELDS = 500
