// ddgi-client: a scriptable command-line client of the DDGI render service, one command per RPC,
// JSON on stdout (docs/service.md).
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cli.h"

namespace ddgi::client {
namespace {

const std::vector<CommandSpec>& commands() {
  static const std::vector<CommandSpec> all = [] {
    std::vector<CommandSpec> list;
    add_session_commands(list);
    add_frame_commands(list);
    add_field_commands(list);
    add_probe_commands(list);
    return list;
  }();
  return all;
}

void print_usage(FILE* out) {
  std::fprintf(out,
               "usage: ddgi-client [connection flags] COMMAND [arguments and flags]\n\n"
               "Talks to a ddgi-server; prints one JSON document per call on stdout. Exit code 0 "
               "on success,\n1 when the server refused or could not be reached (the gRPC code is "
               "in the JSON),\n2 for bad usage.\n\ncommands:\n");
  for (const CommandSpec& command : commands()) {
    std::fprintf(out, "  %-12s %s\n  %-12s   %s\n", command.name.c_str(), command.usage.c_str(), "",
                 command.help.c_str());
  }
  std::fprintf(out, "\n%s", connection_usage());
}

bool is_global_boolean(const std::string& name) {
  return name == "tls" || name == "help";
}

// The command is the first argument that is neither a flag nor a flag's value.
int command_index(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0) return i;
    const std::string name = arg.substr(2, arg.find('=') - 2);
    if (arg.find('=') == std::string::npos && !is_global_boolean(name)) ++i;  // skip its value
  }
  return -1;
}

int run(int argc, char** argv) {
  const int index = command_index(argc, argv);
  if (index < 0 || std::strcmp(argv[index], "help") == 0) {
    const bool asked = index >= 0 || (argc > 1 && std::strcmp(argv[1], "--help") == 0);
    print_usage(asked ? stdout : stderr);
    return asked ? 0 : kExitUsage;
  }
  const std::string name = argv[index];
  auto spec = std::find_if(commands().begin(), commands().end(),
                           [&](const CommandSpec& c) { return c.name == name; });
  if (spec == commands().end()) {
    std::fprintf(stderr, "ddgi-client: unknown command '%s' (see --help)\n", name.c_str());
    return kExitUsage;
  }
  std::vector<std::string> known = connection_flags();
  known.insert(known.end(), spec->flags.begin(), spec->flags.end());
  std::vector<std::string> booleans = spec->boolean_flags;
  booleans.push_back("tls");
  booleans.push_back("help");
  auto flags = Flags::parse(argc, argv, known, booleans);
  if (!flags.ok()) return report(flags.error().with_context(name));
  if (flags->has("help")) {
    std::printf("usage: ddgi-client %s %s\n  %s\n\n%s", spec->name.c_str(), spec->usage.c_str(),
                spec->help.c_str(), connection_usage());
    return 0;
  }
  auto connection = connection_options(*flags);
  if (!connection.ok()) return report(connection.error());
  Cli cli{*flags, *connection, make_channel(*connection), nullptr};
  cli.stub = v1::RenderService::NewStub(cli.channel);
  return spec->run(cli);
}

}  // namespace
}  // namespace ddgi::client

int main(int argc, char** argv) {
  return ddgi::client::run(argc, argv);
}
