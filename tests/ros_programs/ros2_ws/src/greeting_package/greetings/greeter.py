"""The package's own module, imported by its nodes as `from greetings.greeter import greeting`."""


def greeting(name):
    return "Hello, %s!" % (name or "nobody")
