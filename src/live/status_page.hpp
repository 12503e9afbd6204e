// SPDX-License-Identifier: Apache-2.0
#pragma once
// The shore status page: one self-contained HTML document (no external assets) for a phone.
#include <string_view>

namespace coxswain::live {

inline constexpr std::string_view kStatusPageHtml = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>coxswain</title>
<style>
body{font-family:sans-serif;margin:1em;background:#f4f6f8}
h1{font-size:1.3em}#state{font-size:1.6em;font-weight:bold}
.bad{color:#b00}.ok{color:#070}button{font-size:1.2em;margin:.3em;padding:.5em 1em}
table{border-collapse:collapse}td{padding:.2em .6em;border-bottom:1px solid #ccc}
input,select{font-size:1.1em;margin:.2em}
</style></head><body>
<h1>coxswain</h1>
<div id="state">...</div>
<div id="hold"></div>
<div id="wait"></div>
<table id="devices"></table>
<div id="controls"></div>
<p><label>Token <input id="token" type="password" autocomplete="current-password"></label></p>
<p><button onclick="send('start')">Start</button>
<button onclick="send('hold')">Hold</button>
<button onclick="send('resume')">Resume</button></p>
<p><select id="colour"><option>red</option><option>green</option><option>blue</option>
<option>yellow</option><option>orange</option><option>purple</option><option>black</option>
<option>white</option></select>
<select id="shape"><option>triangle</option><option>rectangle</option><option>cross</option>
<option>circle</option></select>
<button onclick="send('target',{colour:v('colour'),shape:v('shape')})">Set target</button></p>
<div id="result"></div>
<script>
function v(id){return document.getElementById(id).value}
function t(id,s,c){var e=document.getElementById(id);e.textContent=s;if(c!==undefined)e.className=c}
var tok=document.getElementById('token');tok.value=localStorage.getItem('coxswain_token')||'';
tok.onchange=function(){localStorage.setItem('coxswain_token',tok.value)};
function send(cmd,body){
 fetch('/api/'+cmd,{method:'POST',headers:{'X-Coxswain-Token':tok.value,
  'Content-Type':'application/json'},body:JSON.stringify(body||{})})
 .then(function(r){return r.text().then(function(x){t('result',cmd+': '+x,r.ok?'ok':'bad')})})
 .catch(function(e){t('result',cmd+': '+e,'bad')})}
function refresh(){
 fetch('/api/status',{headers:{'X-Coxswain-Token':tok.value}}).then(function(r){return r.json()}).then(function(s){
  t('state',s.state_path,s.holding?'bad':'ok');
  t('hold',s.holding?'holding: '+s.hold_reason:'');
  t('wait',s.waiting_for?'waiting for: '+s.waiting_for:'');
  var c=s.controls||{enabled:true};
  t('controls',c.enabled?'':'Controls disabled: '+c.why+'. To enable them: '+c.how+'.',
    c.enabled?'ok':'bad');
  document.querySelectorAll('button,#token').forEach(function(b){b.disabled=!c.enabled});
  var tb=document.getElementById('devices');tb.innerHTML='';
  Object.keys(s.devices).forEach(function(k){var d=s.devices[k];var r=tb.insertRow();
   r.insertCell().textContent=k;var c=r.insertCell();c.textContent=d.state;
   c.className=(d.state=='running'||d.state=='disabled')?'ok':'bad';
   r.insertCell().textContent=d.rate_hz.toFixed(1)+' Hz';r.insertCell().textContent=d.detail});
 }).catch(function(){t('state','no connection','bad')})}
refresh();setInterval(refresh,1000);
</script></body></html>
)HTML";

}  // namespace coxswain::live
