#!/usr/bin/env python3
"""The runtime records onto a compute-only queue (an engine's async compute queue): every command it
records, and every pipeline stage and access it names in barriers and timestamps, is one that the
Vulkan specification lists for compute queues ("Supported Queue Types"; graphics-only ones such as
vkCmdBlitImage, or a fragment stage, would fail there). compute_queue_tests runs the runtime on a
family the validation layer sees as compute-only; the sources are read here too, for the paths that
the test device does not take (those for devices that lack a format or a feature).

    tests/compute_queue_commands.py [ROOT]
"""
import pathlib
import re
import sys

# Commands a queue family with VK_QUEUE_COMPUTE_BIT and no VK_QUEUE_GRAPHICS_BIT accepts (those a
# runtime of this kind can use; no draw, render-pass, blit, resolve or depth-stencil command).
COMMANDS = {
    "vkCmdBindDescriptorSets", "vkCmdBindPipeline", "vkCmdClearColorImage", "vkCmdCopyBuffer", "vkCmdCopyBufferToImage",
    "vkCmdCopyImage", "vkCmdCopyImageToBuffer", "vkCmdDispatch", "vkCmdDispatchBase", "vkCmdDispatchIndirect", "vkCmdFillBuffer",
    "vkCmdPipelineBarrier", "vkCmdPushConstants", "vkCmdResetEvent", "vkCmdResetQueryPool", "vkCmdSetEvent", "vkCmdUpdateBuffer",
    "vkCmdWaitEvents", "vkCmdWriteTimestamp",
}
# Pipeline stages a compute queue supports (no vertex, tessellation, geometry, fragment or attachment stage).
STAGES = {
    "TOP_OF_PIPE_BIT", "BOTTOM_OF_PIPE_BIT", "DRAW_INDIRECT_BIT", "COMPUTE_SHADER_BIT", "TRANSFER_BIT", "HOST_BIT", "ALL_COMMANDS_BIT",
}
# Accesses those stages make (no index, vertex-attribute, input-attachment or attachment access).
ACCESSES = {
    "INDIRECT_COMMAND_READ_BIT", "UNIFORM_READ_BIT", "SHADER_READ_BIT", "SHADER_WRITE_BIT", "TRANSFER_READ_BIT", "TRANSFER_WRITE_BIT",
    "HOST_READ_BIT", "HOST_WRITE_BIT", "MEMORY_READ_BIT", "MEMORY_WRITE_BIT",
}


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    files = sorted(p for d in ("runtime/src", "runtime/include") for p in (root / d).rglob("*") if p.suffix in (".cpp", ".h"))
    found = {"command": set(), "stage": set(), "access": set()}
    problems = []
    for path in files:
        for number, line in enumerate(path.read_text().splitlines(), 1):
            code = line.split("//", 1)[0]  # comments may name what the code does not do
            for kind, pattern, allowed in (("command", r"\b(vkCmd\w+)", COMMANDS),
                                           ("stage", r"\bVK_PIPELINE_STAGE_(\w+)", STAGES),
                                           ("access", r"\bVK_ACCESS_(\w+)", ACCESSES)):
                for name in re.findall(pattern, code):
                    found[kind].add(name)
                    if name not in allowed:
                        problems.append(f"{path.relative_to(root)}:{number}: {kind} {name} is not one a compute-only queue accepts")
    # The scan must see the runtime's commands, or it checks nothing.
    if "vkCmdDispatch" not in found["command"] or "COMPUTE_SHADER_BIT" not in found["stage"]:
        problems.append("no vkCmdDispatch or compute stage found: the runtime's sources were not read")
    for p in problems:
        print(f"FAIL: {p}", file=sys.stderr)
    if problems:
        return 1
    print(f"compute_queue_commands: ok ({len(found['command'])} commands, {len(found['stage'])} stages, "
          f"{len(found['access'])} accesses in {len(files)} files)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
