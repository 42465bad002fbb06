"""The host platform's build script: the host's gcc and binutils, and PlatformIO's own program
builder (the project's src/ and its libraries from lib/, each with its library.json flags)."""
from SCons.Script import Default, DefaultEnvironment

env = DefaultEnvironment()
env.Replace(AR="ar", AS="as", CC="gcc", CXX="g++", RANLIB="ranlib", OBJCOPY="objcopy",
            SIZETOOL="size", SIZEPRINTCMD="$SIZETOOL $SOURCES")
Default([env.BuildProgram()])
