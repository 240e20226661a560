HELP = "Print the scene file reference (Markdown) generated from the schema."
EXAMPLES = "  gearbox scene-doc > docs/scene.md\n"


def add_arguments(parser):
    pass


def run(args):
    from ..scene import schema_markdown

    print(schema_markdown())
    return 0
